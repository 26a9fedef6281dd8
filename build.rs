//! Stamps the build with what it is: the git revision (short hash, `-dirty` when tracked files
//! differ from it) and the UTC build date, for `armjog --version` and the man page.
//!
//! A build never fails for lack of git: outside a git checkout (a crates tarball), or without
//! `git` on the PATH, the revision reads `unknown`.

use std::path::Path;
use std::process::Command;

fn main() {
    let manifest_dir = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_else(|_| ".".to_string());
    let root = Path::new(&manifest_dir);
    let revision = git_revision(root).unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=ARMJOG_BUILD_REVISION={revision}");
    println!("cargo:rustc-env=ARMJOG_BUILD_DATE={}", build_date());
    println!("cargo:rerun-if-env-changed=SOURCE_DATE_EPOCH");
    // Edits to the sources can make the tree dirty; they rebuild the crate anyway.
    println!("cargo:rerun-if-changed=src");
    println!("cargo:rerun-if-changed=Cargo.toml");
    for file in git_files_to_watch(root) {
        println!("cargo:rerun-if-changed={file}");
    }
}

/// Runs `git` in `root`; its trimmed stdout when it succeeds.
fn git(root: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(root)
        .args(args)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// The checkout's own `.git` (a directory, or a worktree's file): without it the package is not
/// a checkout, even when some enclosing directory is one.
fn is_checkout(root: &Path) -> bool {
    root.join(".git").exists()
}

/// `508af6a`, or `508af6a-dirty` when a tracked file is modified.
fn git_revision(root: &Path) -> Option<String> {
    if !is_checkout(root) {
        return None;
    }
    let hash = git(root, &["rev-parse", "--short=7", "HEAD"])?;
    if hash.is_empty() {
        return None;
    }
    let status = git(root, &["status", "--porcelain", "--untracked-files=no"])?;
    Some(if status.is_empty() {
        hash
    } else {
        format!("{hash}-dirty")
    })
}

/// HEAD, the ref it points to (loose, or the packed refs) and the index, so a commit, a
/// checkout or a `git add` stamps the new revision. Only existing files: cargo reruns a script
/// on every build when a watched file is missing.
fn git_files_to_watch(root: &Path) -> Vec<String> {
    if !is_checkout(root) {
        return Vec::new();
    }
    let mut paths = vec![
        "HEAD".to_string(),
        "index".to_string(),
        "packed-refs".to_string(),
    ];
    if let Some(reference) = git(root, &["symbolic-ref", "-q", "HEAD"]) {
        paths.push(reference);
    }
    paths
        .iter()
        .filter_map(|p| {
            git(
                root,
                &["rev-parse", "--path-format=absolute", "--git-path", p],
            )
        })
        .filter(|p| Path::new(p).exists())
        .collect()
}

/// The UTC date of the build, `YYYY-MM-DD`; `SOURCE_DATE_EPOCH` (reproducible builds) wins.
fn build_date() -> String {
    let now = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<i64>().ok())
        .and_then(|secs| time::OffsetDateTime::from_unix_timestamp(secs).ok())
        .unwrap_or_else(time::OffsetDateTime::now_utc);
    // `Date`'s Display is ISO 8601: `2026-12-01`.
    now.date().to_string()
}
