//! `armjog --version` says what the build is: `armjog 0.1.0 (508af6a 2026-12-01)`, the
//! version, the git revision (`-dirty` for modified tracked files, `unknown` outside a git
//! checkout) and the UTC build date.

use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_armjog");

/// `(revision, date)` from `armjog VERSION (REVISION DATE)`, or why the line is not that.
fn parse(line: &str) -> Result<(&str, &str), String> {
    let rest = line
        .strip_prefix(&format!("armjog {} (", env!("CARGO_PKG_VERSION")))
        .ok_or("not `armjog VERSION (`")?;
    let inner = rest.strip_suffix(')').ok_or("no closing parenthesis")?;
    let (revision, date) = inner.split_once(' ').ok_or("not `REVISION DATE`")?;
    let hash = revision.strip_suffix("-dirty").unwrap_or(revision);
    let is_hash = hash.len() >= 7 && hash.bytes().all(|b| b.is_ascii_hexdigit());
    if !(is_hash || revision == "unknown") {
        return Err(format!("revision {revision:?}"));
    }
    let bytes = date.as_bytes();
    let is_date = bytes.len() == 10
        && bytes.iter().enumerate().all(|(i, b)| match i {
            4 | 7 => *b == b'-',
            _ => b.is_ascii_digit(),
        });
    if !is_date {
        return Err(format!("date {date:?}"));
    }
    Ok((revision, date))
}

#[test]
fn the_parser_takes_the_documented_forms_only() {
    let v = env!("CARGO_PKG_VERSION");
    assert!(parse(&format!("armjog {v} (508af6a 2026-12-01)")).is_ok());
    assert!(parse(&format!("armjog {v} (508af6a-dirty 2026-12-01)")).is_ok());
    assert!(parse(&format!("armjog {v} (unknown 2026-12-01)")).is_ok());
    for bad in [
        format!("armjog {v}"),
        format!("armjog {v} (508af6a)"),
        format!("armjog {v} (508af6a 2026-12-1)"),
        format!("armjog {v} (xyz 2026-12-01)"),
        format!("armjog {v} (508af6a 01.12.2026)"),
    ] {
        assert!(parse(&bad).is_err(), "{bad}");
    }
}

#[test]
fn version_prints_the_revision_and_the_utc_build_date() {
    let out = Command::new(BIN)
        .arg("--version")
        .output()
        .expect("run armjog --version");
    assert!(out.status.success(), "{out:?}");
    let stdout = String::from_utf8(out.stdout).expect("utf-8");
    let line = stdout.strip_suffix('\n').expect("one line");
    let (revision, date) = parse(line).unwrap_or_else(|why| panic!("{line:?}: {why}"));

    // Built today or earlier (UTC), never in the future.
    let today = time::OffsetDateTime::now_utc().date().to_string();
    assert!(date <= today.as_str(), "built {date}, today {today}");

    // From this checkout, the revision is its HEAD.
    let root = env!("CARGO_MANIFEST_DIR");
    let head = Command::new("git")
        .args(["-C", root, "rev-parse", "--short=7", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string());
    if let Some(head) = head
        && std::path::Path::new(root).join(".git").exists()
    {
        assert_eq!(
            revision.strip_suffix("-dirty").unwrap_or(revision),
            head,
            "{line}"
        );
    }
}
