//! A small Rust source scanner for `imports.rs`: every path a file names, with its line.
//!
//! Not a parser: enough lexing to be exact about what counts. Plain comments and the contents
//! of string and char literals are blanked (they name no module); doc comments are kept apart,
//! as an intra-doc link (`[`crate::x`]`) is a reference too. Use trees are flattened
//! (`use crate::{a, b::{c, d}}` gives `crate::a`, `crate::b::c`, `crate::b::d`), and `super`
//! chains are resolved against the file's module path plus the inline `mod x { .. }` around
//! them, so `super::super::` is known to stay inside a layer or to climb to the crate root.

/// One path named in a source file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PathRef {
    /// 1-based line of the path's first segment (of the group item, in a use tree).
    pub line: usize,
    /// The path as written, flattened: `["crate", "console", "jog", "JogMotion"]`.
    pub segments: Vec<String>,
    /// Named in a doc comment rather than in code.
    pub in_docs: bool,
    /// For `crate::x::..` and a `super::..` chain that reaches the crate root: the top-level
    /// module `x` it enters (`*` for a glob of the root). `None` for a path that stays inside
    /// the file's own top-level module, and for paths into other crates (`std`, `tokio`).
    pub crate_module: Option<String>,
}

impl PathRef {
    pub fn text(&self) -> String {
        self.segments.join("::")
    }
}

/// Every path in `src`, a file at `rel_path` under `src/` (e.g. `link/driver/mod.rs`).
pub fn path_refs(rel_path: &str, src: &str) -> Vec<PathRef> {
    let file_module = module_path(rel_path);
    let blanked = blank(src);
    let mut refs = scan_tokens(&tokenize(&blanked.code), &file_module, false);
    refs.extend(scan_tokens(&tokenize(&blanked.docs), &file_module, true));
    refs.sort_by_key(|r| r.line);
    refs
}

/// The module path of a file under `src/`: `link/driver/mod.rs` is `[link, driver]`,
/// `link/interface.rs` is `[link, interface]`.
pub fn module_path(rel_path: &str) -> Vec<String> {
    let trimmed = rel_path.strip_suffix(".rs").unwrap_or(rel_path);
    let mut parts: Vec<String> = trimmed.split('/').map(str::to_string).collect();
    if parts.last().is_some_and(|last| last == "mod") {
        parts.pop();
    }
    parts
}

struct Blanked {
    /// The source with comments and literal contents replaced by spaces (newlines kept).
    code: Vec<char>,
    /// Only the text of doc comments, everything else spaces (newlines kept).
    docs: Vec<char>,
}

fn blank(src: &str) -> Blanked {
    let s: Vec<char> = src.chars().collect();
    let mut code = s.clone();
    let mut docs: Vec<char> = s
        .iter()
        .map(|&c| if c == '\n' { '\n' } else { ' ' })
        .collect();
    let at = |i: usize| s.get(i).copied();
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        let prev_is_ident = i > 0 && is_ident_char(s[i - 1]);
        if c == '/' && at(i + 1) == Some('/') {
            let end = (i..s.len()).find(|&j| s[j] == '\n').unwrap_or(s.len());
            let doc = (at(i + 2) == Some('/') && at(i + 3) != Some('/')) || at(i + 2) == Some('!');
            if doc {
                docs[i + 3..end].copy_from_slice(&s[i + 3..end]);
            }
            blank_range(&mut code, i, end);
            i = end;
        } else if c == '/' && at(i + 1) == Some('*') {
            let doc = matches!(at(i + 2), Some('*' | '!')) && at(i + 3) != Some('/');
            let mut depth = 0;
            let mut j = i;
            while j < s.len() {
                if s[j] == '/' && at(j + 1) == Some('*') {
                    depth += 1;
                    j += 2;
                } else if s[j] == '*' && at(j + 1) == Some('/') {
                    depth -= 1;
                    j += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    j += 1;
                }
            }
            let end = j.min(s.len());
            if doc {
                docs[i..end].copy_from_slice(&s[i..end]);
            }
            blank_range(&mut code, i, end);
            i = end;
        } else if let Some(end) = raw_string_end(&s, i).filter(|_| !prev_is_ident) {
            blank_range(&mut code, i + 1, end.saturating_sub(1));
            i = end;
        } else if c == '"' {
            let mut j = i + 1;
            while j < s.len() && s[j] != '"' {
                j += if s[j] == '\\' { 2 } else { 1 };
            }
            blank_range(&mut code, i + 1, j.min(s.len()));
            i = j + 1;
        } else if c == '\'' && at(i + 1) == Some('\\') {
            let end = (i + 3..s.len()).find(|&j| s[j] == '\'').unwrap_or(s.len());
            blank_range(&mut code, i + 1, end);
            i = end + 1;
        } else if c == '\'' && at(i + 2) == Some('\'') {
            blank_range(&mut code, i + 1, i + 2);
            i += 3;
        } else {
            // Anything else, a lifetime or label included, is code.
            i += 1;
        }
    }
    Blanked { code, docs }
}

/// Where a raw string starting at `i` (`r"..."`, `r#"..."#`, `br"..."`) ends, if one does.
fn raw_string_end(s: &[char], i: usize) -> Option<usize> {
    let mut j = match (s.get(i), s.get(i + 1)) {
        (Some('r'), _) => i + 1,
        (Some('b'), Some('r')) => i + 2,
        _ => return None,
    };
    let hashes = s[j..].iter().take_while(|&&c| c == '#').count();
    j += hashes;
    if s.get(j) != Some(&'"') {
        return None;
    }
    let mut k = j + 1;
    while k < s.len() {
        if s[k] == '"'
            && s[k + 1..]
                .iter()
                .take(hashes)
                .filter(|&&c| c == '#')
                .count()
                == hashes
        {
            return Some(k + 1 + hashes);
        }
        k += 1;
    }
    Some(s.len())
}

fn blank_range(chars: &mut [char], from: usize, to: usize) {
    for c in chars.iter_mut().take(to).skip(from) {
        if *c != '\n' {
            *c = ' ';
        }
    }
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

#[derive(Debug, Clone, PartialEq, Eq)]
enum Tok {
    Ident(String),
    PathSep,
    Open,
    Close,
    Comma,
    Star,
    Other(char),
}

struct Token {
    tok: Tok,
    line: usize,
}

fn tokenize(chars: &[char]) -> Vec<Token> {
    let mut tokens = Vec::new();
    let mut line = 1;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let tok = if c == '\n' {
            line += 1;
            i += 1;
            continue;
        } else if c.is_whitespace() {
            i += 1;
            continue;
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && is_ident_char(chars[i]) {
                i += 1;
            }
            tokens.push(Token {
                tok: Tok::Ident(chars[start..i].iter().collect()),
                line,
            });
            continue;
        } else if c.is_ascii_digit() {
            while i < chars.len() && (is_ident_char(chars[i]) || chars[i] == '.') {
                i += 1;
            }
            tokens.push(Token {
                tok: Tok::Other('0'),
                line,
            });
            continue;
        } else if c == ':' && chars.get(i + 1) == Some(&':') {
            i += 1;
            Tok::PathSep
        } else {
            match c {
                '{' => Tok::Open,
                '}' => Tok::Close,
                ',' => Tok::Comma,
                '*' => Tok::Star,
                other => Tok::Other(other),
            }
        };
        tokens.push(Token { tok, line });
        i += 1;
    }
    tokens
}

fn scan_tokens(tokens: &[Token], file_module: &[String], in_docs: bool) -> Vec<PathRef> {
    let mut refs = Vec::new();
    // Inline modules open at this point: (name, brace depth inside them).
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut pending_mod: Option<String> = None;
    let mut depth = 0;
    let mut i = 0;
    while i < tokens.len() {
        let prev = i.checked_sub(1).map(|p| &tokens[p].tok);
        let starts_path = match (&tokens[i].tok, prev) {
            // `use {a, b}`: a use tree with no prefix.
            (Tok::Open, Some(Tok::Ident(word))) => word == "use",
            (Tok::Ident(_), Some(Tok::PathSep)) => {
                // `::tokio::x` (a leading `::`) starts a path; `a::b` continues one.
                !matches!(
                    i.checked_sub(2).map(|p| &tokens[p].tok),
                    Some(Tok::Ident(_) | Tok::Other('>'))
                )
            }
            (Tok::Ident(_), _) => true,
            _ => false,
        };
        if starts_path {
            let (paths, next) = parse_tree(tokens, i);
            let mut module: Vec<String> = file_module.to_vec();
            module.extend(inline.iter().map(|(name, _)| name.clone()));
            for (segments, line) in paths {
                if let Some(path_ref) = classify(segments, line, &module, in_docs) {
                    refs.push(path_ref);
                }
            }
            // A use tree's braces are balanced and its own: they open no block.
            if tree_has_braces(tokens, i, next) {
                i = next;
                continue;
            }
        }
        match &tokens[i].tok {
            Tok::Open => {
                depth += 1;
                if let Some(name) = pending_mod.take() {
                    inline.push((name, depth));
                }
            }
            Tok::Close => {
                depth = depth.saturating_sub(1);
                while inline.last().is_some_and(|(_, d)| *d > depth) {
                    inline.pop();
                }
            }
            Tok::Ident(word) if word == "mod" => {
                if let Some(Tok::Ident(name)) = tokens.get(i + 1).map(|t| &t.tok) {
                    pending_mod = Some(name.clone());
                }
            }
            Tok::Other(';') => pending_mod = None,
            _ => {}
        }
        i += 1;
    }
    refs
}

fn tree_has_braces(tokens: &[Token], from: usize, to: usize) -> bool {
    tokens[from..to.min(tokens.len())]
        .iter()
        .any(|t| matches!(t.tok, Tok::Open | Tok::Close))
}

/// Keeps the paths that start with `crate`, `super`, or an identifier that could name another
/// crate, and resolves the crate-internal ones to the top-level module they enter.
fn classify(
    segments: Vec<String>,
    line: usize,
    module: &[String],
    in_docs: bool,
) -> Option<PathRef> {
    let first = segments.first()?.as_str();
    let crate_module = match first {
        "crate" => Some(segments.get(1)?.clone()),
        "super" => {
            let climbs = segments.iter().take_while(|s| *s == "super").count();
            if climbs < module.len() {
                None
            } else {
                // Exactly at the crate root; more `super`s than that would not compile.
                Some(segments.get(climbs)?.clone())
            }
        }
        _ if in_docs || segments.len() < 2 => return None,
        _ => None,
    };
    if in_docs && crate_module.is_none() {
        return None;
    }
    Some(PathRef {
        line,
        segments,
        in_docs,
        crate_module,
    })
}

/// Flattens the path or use tree starting at `tokens[i]`: each path with the line of its first
/// segment, and the index of the first token after the tree.
fn parse_tree(tokens: &[Token], mut i: usize) -> (Vec<(Vec<String>, usize)>, usize) {
    let line = tokens.get(i).map_or(0, |t| t.line);
    let mut segments: Vec<String> = Vec::new();
    loop {
        match tokens.get(i).map(|t| &t.tok) {
            Some(Tok::Ident(name)) => {
                segments.push(name.clone());
                i += 1;
            }
            Some(Tok::Star) => {
                segments.push("*".into());
                return (vec![(segments, line)], i + 1);
            }
            Some(Tok::Open) => {
                let (items, next) = parse_group(tokens, i + 1);
                let flattened = items
                    .into_iter()
                    .map(|(tail, item_line)| {
                        let mut path = segments.clone();
                        path.extend(tail);
                        (path, item_line)
                    })
                    .collect();
                return (flattened, next);
            }
            _ => break,
        }
        if matches!(tokens.get(i).map(|t| &t.tok), Some(Tok::PathSep)) {
            i += 1;
        } else {
            break;
        }
    }
    let paths = if segments.is_empty() {
        Vec::new()
    } else {
        vec![(segments, line)]
    };
    (paths, i)
}

/// The items of a `{ .. }` group whose `{` is just before `tokens[i]`, up to its `}`.
fn parse_group(tokens: &[Token], mut i: usize) -> (Vec<(Vec<String>, usize)>, usize) {
    let mut items = Vec::new();
    while i < tokens.len() {
        match tokens[i].tok {
            Tok::Close => return (items, i + 1),
            Tok::Comma => i += 1,
            _ => {
                let (paths, next) = parse_tree(tokens, i);
                items.extend(paths);
                i = next.max(i + 1);
                // Skip the rest of the item (`as name`) up to its `,` or the group's `}`.
                let mut nested = 0usize;
                while i < tokens.len() {
                    match tokens[i].tok {
                        Tok::Open => nested += 1,
                        Tok::Close if nested == 0 => break,
                        Tok::Close => nested -= 1,
                        Tok::Comma if nested == 0 => break,
                        _ => {}
                    }
                    i += 1;
                }
            }
        }
    }
    (items, i)
}
