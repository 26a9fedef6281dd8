//! Hostile local files: `/dev/zero` and oversized files are refused at once, naming the file and
//! the limit, instead of being read until memory runs out.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A path in a fresh directory, removed when the `TempDir` is dropped.
fn temp_path(name: &str) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    (dir, path)
}

/// Runs armjog with `args`; it must exit within 10 s (killed otherwise). Returns (status, stderr).
fn run_armjog(args: &[&str]) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_armjog"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("armjog {args:?} still running after 10 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut stderr = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut stderr).unwrap();
    (status.code().unwrap_or(-1), stderr)
}

fn assert_refused(args: &[&str], file: &str, limit: &str) {
    let (code, stderr) = run_armjog(args);
    assert!(code == 1 || code == 2, "exit status {code}: {stderr}");
    assert!(stderr.contains(file), "names the file: {stderr}");
    assert!(stderr.contains(limit), "names the limit: {stderr}");
}

#[cfg(unix)]
#[test]
fn keymap_dev_zero_is_refused_at_once() {
    assert_refused(&["--keymap", "/dev/zero"], "/dev/zero", "1 MB");
}

#[cfg(unix)]
#[test]
fn positions_dev_zero_is_refused_at_once() {
    assert_refused(&["--positions", "/dev/zero"], "/dev/zero", "16 MB");
}

#[test]
fn a_17_mb_positions_file_is_refused_and_left_untouched() {
    let (_dir, path) = temp_path("book.json");
    let contents = vec![b' '; 17 * 1024 * 1024];
    std::fs::write(&path, &contents).unwrap();
    let shown = path.display().to_string();
    assert_refused(&["--positions", &shown], &shown, "16 MB");
    assert_eq!(std::fs::read(&path).unwrap(), contents, "nothing written");
}

#[test]
fn a_keymap_one_byte_over_1_mb_is_refused() {
    let (_dir, path) = temp_path("keymap.json");
    std::fs::write(&path, vec![b' '; 1024 * 1024 + 1]).unwrap();
    let shown = path.display().to_string();
    assert_refused(&["--keymap", &shown], &shown, "1 MB");
}

/// A valid built-in keymap padded with whitespace to just under the limit.
fn padded_builtin_keymap(path: &Path) {
    let name = armjog::console::keymap::Keymap::builtin_names()
        .next()
        .unwrap();
    let json = armjog::console::keymap::Keymap::builtin_json(name).unwrap();
    let mut text = json.to_string();
    text.push_str(&" ".repeat(1024 * 1024 - text.len()));
    assert_eq!(text.len(), 1024 * 1024);
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_keymap_of_exactly_1_mb_still_loads() {
    let (_dir, path) = temp_path("keymap.json");
    padded_builtin_keymap(&path);
    let shown = path.display().to_string();
    armjog::console::keymap::Keymap::load(&shown).unwrap();
}
