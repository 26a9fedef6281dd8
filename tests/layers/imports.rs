//! The layers point down (issue 10): no module of `src/` imports a layer above it.
//!
//! A source scan, standing in for the crate boundaries a workspace would enforce. Each
//! top-level module of the library has a layer and the list of modules it may import
//! ([`LAYERS`]); any other `crate::x` it names (a `use`, a path in an expression or a type, a
//! `super::super::` chain that climbs to the crate root, a group `use crate::{a, b}`, an
//! intra-doc link) fails the test with the file, the line and the path.
//!
//! "No IO" for the pure protocol layers (`talos`, `kortex`) means: no sockets, files,
//! processes, threads, environment, terminal or async runtime. They may not name `tokio`
//! (runtime, net, fs, io, time), `tokio_modbus`, `std::{net, fs, process, thread, env, os}`,
//! `std::io` beyond its error types, the terminal crates, `dirs`, the log writers
//! (`tracing_subscriber`, `tracing_appender`), nor the crate's IO helpers (`files`, `logging`,
//! `net`). Allowed: `tokio_util::codec` (the `Decoder`/`Encoder` traits are pure transforms of
//! a byte buffer), `bytes`, `std::io::{Error, ErrorKind, Result}` (the codec traits' error
//! type) and the `tracing` facade (a log call does no IO of its own).

use crate::scan;

use std::path::Path;

use scan::{PathRef, path_refs};

/// Every top-level module of the library, bottom up, with what it may import from the crate
/// besides itself. A new module needs a row here (the test says so). A row a layer, by hand:
/// rustfmt would put the longer lists one name a line.
#[rustfmt::skip]
const LAYERS: &[(&str, &[&str])] = &[
    // The sanitiser of text from outside and the name rule: pure, the bottom.
    ("text", &[]),
    // The Kinova register map: pure.
    ("kortex", &[]),
    // The Talos ICD codec: pure; its hardware companion ICD names flags as the register map does.
    ("talos", &["kortex", "text"]),
    // Bounded reads of local files, and the log writer: leaves.
    ("files", &[]),
    ("logging", &[]),
    // An IO helper shared by link and sim (sockets, framing), should one be added.
    ("net", &["talos", "kortex", "text"]),
    // The arm links and the driver.
    (
        "link",
        &["talos", "kortex", "net", "files", "logging", "text"],
    ),
    // The simulated arm: serves the codecs, never uses the links.
    (
        "sim",
        &["talos", "kortex", "net", "files", "logging", "text"],
    ),
    // The console drives links; the simulator is wired to it by the cli.
    (
        "console",
        &["talos", "kortex", "net", "files", "logging", "link", "text"],
    ),
    // The front ends: everything.
    (
        "cli",
        &["talos", "kortex", "net", "files", "logging", "link", "sim", "console", "text"],
    ),
];

/// The layers that do no IO.
const PURE: &[&str] = &["talos", "kortex", "text"];

/// Paths into IO, forbidden in [`PURE`] layers: a path starting with one of these.
const IO_PATHS: &[&[&str]] = &[
    &["tokio"],
    &["tokio_modbus"],
    &["crossterm"],
    &["ratatui"],
    &["dirs"],
    &["tracing_subscriber"],
    &["tracing_appender"],
    &["std", "net"],
    &["std", "fs"],
    &["std", "process"],
    &["std", "thread"],
    &["std", "env"],
    &["std", "os"],
];

/// What a pure layer may name in `std::io`: the codec traits' error type.
const STD_IO_ALLOWED: &[&str] = &["Error", "ErrorKind", "Result"];

fn allowed_imports(layer: &str) -> Option<&'static [&'static str]> {
    LAYERS
        .iter()
        .find(|(name, _)| *name == layer)
        .map(|(_, allowed)| *allowed)
}

/// What is wrong with `path_ref` in a file of `layer`, if anything.
fn judge(layer: &str, path_ref: &PathRef) -> Option<String> {
    let allowed = allowed_imports(layer)?;
    if let Some(target) = &path_ref.crate_module {
        if target == layer || target == "self" {
            return None;
        }
        if target == "*" {
            return Some(format!(
                "a glob of the crate root imports every layer; {layer} may import only: {}",
                allowed.join(", ")
            ));
        }
        if allowed_imports(target).is_none() || allowed.contains(&target.as_str()) {
            // Not a layer (an item of lib.rs), or a layer below.
            return None;
        }
        return Some(format!(
            "{target} is not below {layer}; {layer} may import only: {}",
            if allowed.is_empty() {
                "nothing of the crate".to_string()
            } else {
                allowed.join(", ")
            }
        ));
    }
    if PURE.contains(&layer) && !path_ref.in_docs && is_io(&path_ref.segments) {
        return Some(format!(
            "{layer} is pure and does no IO (tests/layers/imports.rs says what counts as IO)"
        ));
    }
    None
}

fn is_io(segments: &[String]) -> bool {
    let starts_with = |prefix: &[&str]| {
        segments.len() >= prefix.len() && prefix.iter().zip(segments).all(|(p, s)| p == s)
    };
    if IO_PATHS.iter().any(|prefix| starts_with(prefix)) {
        return true;
    }
    // `std::io::Read`, `std::io::stdin`, `std::io::{Read, Write}`: only the error types pass. A
    // bare `std::io` (the module itself) names nothing yet.
    starts_with(&["std", "io"])
        && segments
            .get(2)
            .is_some_and(|item| !STD_IO_ALLOWED.contains(&item.as_str()))
}

/// The violations in one file at `rel_path` under `src/`, one line each:
/// `src/link/interface.rs:8: link imports `crate::console::jog::JogMotion`: ...`.
fn violations(rel_path: &str, src: &str) -> Vec<String> {
    let Some(layer) = rel_path
        .split('/')
        .next()
        .map(|l| l.trim_end_matches(".rs"))
    else {
        return Vec::new();
    };
    path_refs(rel_path, src)
        .iter()
        .filter_map(|path_ref| {
            judge(layer, path_ref).map(|why| {
                format!(
                    "src/{rel_path}:{}: {layer} {} `{}`: {why}",
                    path_ref.line,
                    if path_ref.in_docs {
                        "links in a doc comment to"
                    } else {
                        "imports"
                    },
                    path_ref.text()
                )
            })
        })
        .collect()
}

/// Every `.rs` file under `dir`, as paths relative to `root` with `/` separators.
fn rust_files(root: &Path, dir: &Path, out: &mut Vec<String>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("cannot list {}: {e}", dir.display()))
        .map(|entry| entry.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            rust_files(root, &path, out);
        } else if path.extension().is_some_and(|ext| ext == "rs") {
            let rel = path.strip_prefix(root).expect("under src/");
            let parts: Vec<String> = rel
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            out.push(parts.join("/"));
        }
    }
}

fn src_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The top-level modules `src/lib.rs` declares.
fn library_modules() -> Vec<String> {
    let lib = std::fs::read_to_string(src_dir().join("lib.rs")).expect("src/lib.rs");
    lib.lines()
        .filter_map(|line| {
            let line = line.trim();
            let rest = line
                .strip_prefix("pub mod ")
                .or_else(|| line.strip_prefix("mod "))?;
            rest.strip_suffix(';').map(str::to_string)
        })
        .collect()
}

#[test]
fn no_module_imports_a_layer_above_it() {
    let src = src_dir();
    let mut files = Vec::new();
    rust_files(&src, &src, &mut files);
    let mut found = Vec::new();
    let mut scanned = 0;
    for rel in &files {
        // The crate root declares the layers and the binary wires them: no layer of their own.
        if rel == "lib.rs" || rel == "main.rs" {
            continue;
        }
        let text = std::fs::read_to_string(src.join(rel)).expect("a source file");
        found.extend(violations(rel, &text));
        scanned += 1;
    }
    assert!(
        scanned >= 50,
        "only {scanned} files scanned under {}",
        src.display()
    );
    assert!(
        found.is_empty(),
        "{} upward import(s); move the item down to the layer that needs it (or re-export it \
         from the upper layer), see tests/layers/imports.rs:\n{}",
        found.len(),
        found.join("\n")
    );
}

#[test]
fn every_top_level_module_has_a_layer() {
    let modules = library_modules();
    for expected in ["talos", "kortex", "link", "sim", "console", "cli"] {
        assert!(
            modules.iter().any(|m| m == expected),
            "src/lib.rs no longer declares {expected}: {modules:?}"
        );
    }
    let missing: Vec<_> = modules
        .iter()
        .filter(|m| allowed_imports(m).is_none())
        .collect();
    assert!(
        missing.is_empty(),
        "top-level module(s) {missing:?} have no layer: add a row to LAYERS in tests/layers/imports.rs \
         saying what each may import"
    );
}

// The scanner, fed small sources: each form of import it must catch, and what it must not.

fn check(rel_path: &str, src: &str) -> Vec<String> {
    violations(rel_path, src)
}

#[test]
fn catches_use_crate() {
    let found = check("link/interface.rs", "use crate::console::jog::JogMotion;\n");
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0]
            .starts_with("src/link/interface.rs:1: link imports `crate::console::jog::JogMotion`"),
        "{found:?}"
    );
    assert!(found[0].contains("console is not below link"), "{found:?}");
}

#[test]
fn catches_crate_paths_in_expressions_and_types() {
    let src = "fn log(bytes: &[u8]) -> String {\n    \
               crate::cli::send::spaced_hex(bytes)\n}\n\
               struct Held(Vec<crate::console::jog::JogMotion>);\n";
    let found = check("link/driver/talos_side.rs", src);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(
        found[0].contains(":2: link imports `crate::cli::send::spaced_hex`"),
        "{found:?}"
    );
    assert!(
        found[1].contains(":4: link imports `crate::console::jog::JogMotion`"),
        "{found:?}"
    );
}

#[test]
fn catches_grouped_imports_item_by_item() {
    let found = check(
        "link/x.rs",
        "use crate::{kortex::Pose, sim::arm_model::Arm};\n",
    );
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].contains("`crate::sim::arm_model::Arm`"),
        "{found:?}"
    );

    let src = "use crate::{\n    kortex::Pose,\n    console::{jog::JogMotion, keymap},\n    \
               cli as front,\n};\n";
    let found = check("sim/world.rs", src);
    assert_eq!(found.len(), 3, "{found:?}");
    assert!(
        found[0].contains(":3: sim imports `crate::console::jog::JogMotion`"),
        "{found:?}"
    );
    assert!(
        found[1].contains(":3: sim imports `crate::console::keymap`"),
        "{found:?}"
    );
    assert!(
        found[2].contains(":4: sim imports `crate::cli`"),
        "{found:?}"
    );

    let found = check("talos/frame.rs", "use {crate::link::Dialect, std::fmt};\n");
    assert_eq!(found.len(), 1, "{found:?}");
}

#[test]
fn catches_super_chains_that_climb_out_of_the_layer() {
    // src/link/driver/talos_side.rs is link::driver::talos_side: two supers reach link, three
    // the crate root.
    let file = "link/driver/talos_side.rs";
    assert!(check(file, "use super::super::arm_model::JogMotion;\n").is_empty());
    let found = check(file, "use super::super::super::console::jog::JogMotion;\n");
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].contains("`super::super::super::console::jog::JogMotion`"),
        "{found:?}"
    );
    // A mod.rs is its directory's module: link::driver.
    assert!(check("link/driver/mod.rs", "use super::arm_model::ArmCommand;\n").is_empty());
    assert_eq!(
        check("link/driver/mod.rs", "use super::super::sim::SimArm;\n").len(),
        1
    );
    assert_eq!(
        check("sim/talos_server.rs", "use super::super::link::Dialect;\n").len(),
        1
    );
    // An inline module adds a level: inside `mod tests` of link/interface.rs, two supers stay in link.
    let inline = "mod tests {\n    use super::super::guard::X;\n}\nuse super::guard::Y;\n";
    assert!(check("link/interface.rs", inline).is_empty());
    let inline = "mod tests {\n    use super::super::super::console::X;\n}\n";
    let found = check("link/interface.rs", inline);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains(":2: link imports"), "{found:?}");
    // Once the inline module closes, the level is gone again.
    let after = "mod tests {\n    fn f() { let c = '{'; }\n}\nuse super::super::console::X;\n";
    assert_eq!(check("link/interface.rs", after).len(), 1);
    // `use super::*` at the top of a layer globs the crate root.
    assert_eq!(check("talos/mod.rs", "use super::*;\n").len(), 1);
}

#[test]
fn catches_doc_links_but_not_comments_or_strings() {
    let found = check("link/guard.rs", "//! The guard ([`crate::cli::guard`]).\n");
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains("links in a doc comment to `crate::cli::guard`"));
    assert_eq!(
        check(
            "link/interface.rs",
            "/// See [App](crate::console::App).\nstruct A;\n"
        )
        .len(),
        1
    );
    let quiet = "// crate::console is above us: never import it.\n\
                 const A: &str = \"crate::console::x\";\n\
                 const B: &str = r#\"use crate::cli::send;\"#;\n\
                 const C: char = '\\'';\n\
                 /* crate::sim::x */\n";
    assert!(check("link/interface.rs", quiet).is_empty());
}

#[test]
fn catches_macro_crate_and_leading_colons() {
    assert_eq!(check("link/x.rs", "$crate::console::x!();\n").len(), 1);
    let found = check("kortex/x.rs", "fn f() { ::tokio::spawn(g()); }\n");
    assert_eq!(found.len(), 1, "{found:?}");
}

#[test]
fn same_and_lower_layers_pass() {
    let fine = "use crate::kortex::{Pose, Telemetry};\n\
                use crate::talos::Dialect;\n\
                pub(in crate::link::modbus) struct Hold;\n\
                use crate::link::interface::JogMotion;\n";
    assert!(check("link/driver/mod.rs", fine).is_empty());
    assert!(
        check(
            "console/app/mod.rs",
            "use crate::link::interface::ArmCommand;\n"
        )
        .is_empty()
    );
    assert!(check("cli/sim.rs", "use crate::{console, sim, link};\n").is_empty());
    assert!(
        check(
            "talos/hardware/flags.rs",
            "use crate::kortex::RobotState;\n"
        )
        .is_empty()
    );
    // The register map is the bottom layer.
    assert_eq!(
        check("kortex/flags.rs", "use crate::talos::TalosFrame;\n").len(),
        1
    );
    // The leaves import nothing of the crate.
    assert_eq!(check("files.rs", "use crate::console::keymap;\n").len(), 1);
    // The console drives links but not the simulator nor the front ends.
    assert_eq!(check("console/run.rs", "use crate::cli::guard;\n").len(), 1);
    assert_eq!(
        check("console/run.rs", "use crate::sim::SimArm;\n").len(),
        1
    );
    // A shared IO helper may use the codecs only.
    assert_eq!(
        check("net/framed.rs", "use crate::link::TalosLink;\n").len(),
        1
    );
    assert!(check("net/framed.rs", "use crate::talos::FrameCodec;\n").is_empty());
}

#[test]
fn pure_layers_refuse_io() {
    for io in [
        "use tokio::net::TcpStream;\n",
        "use tokio_modbus::client::Context;\n",
        "use std::fs::File;\n",
        "use std::io::Read;\n",
        "fn f() { let _ = std::io::stdin(); }\n",
        "fn f() { std::thread::sleep(d); }\n",
        "use crate::files::read_to_string_bounded;\n",
        "use crate::net::connect;\n",
    ] {
        assert_eq!(check("talos/frame.rs", io).len(), 1, "{io}");
        assert_eq!(check("kortex/image.rs", io).len(), 1, "{io}");
    }
    let found = check("talos/frame.rs", "use std::{fs, io::Write, fmt};\n");
    assert_eq!(found.len(), 2, "{found:?}");
    let pure = "use bytes::{Buf, BytesMut};\n\
                use tokio_util::codec::{Decoder, Encoder};\n\
                type Error = std::io::Error;\n\
                fn e() -> std::io::Error { std::io::Error::new(std::io::ErrorKind::Other, \"x\") }\n\
                fn w() { tracing::warn!(\"odd frame\"); }\n\
                /// Unlike [`tokio::net::TcpStream`], this reads no socket.\n\
                struct Codec;\n";
    assert!(
        check("talos/frame.rs", pure).is_empty(),
        "{:?}",
        check("talos/frame.rs", pure)
    );
    // IO is the link's and the simulator's business.
    assert!(check("link/talos.rs", "use tokio::net::TcpStream;\n").is_empty());
    assert!(check("sim/talos_server.rs", "use tokio::net::TcpListener;\n").is_empty());
}
