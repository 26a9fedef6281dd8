//! Hostile local files: a device, a FIFO and oversized files are refused at once, naming the
//! file (and the limit or what it is), instead of being read until memory runs out or waiting
//! for a FIFO's writer before the screen starts.

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
        .env(
            "ARMJOG_LOG_DIR",
            std::env::temp_dir().join("armjog-test-logs"),
        )
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

/// What `files::open_regular` says of a device.
const A_DEVICE: &str = "not a regular file (a character device)";
/// And of a FIFO.
const A_FIFO: &str = "not a regular file (a FIFO)";

#[cfg(unix)]
#[test]
fn keymap_dev_zero_is_refused_at_once() {
    assert_refused(&["--keymap", "/dev/zero"], "/dev/zero", A_DEVICE);
}

#[cfg(unix)]
#[test]
fn positions_dev_zero_is_refused_at_once() {
    assert_refused(&["--positions", "/dev/zero"], "/dev/zero", A_DEVICE);
}

/// A FIFO nobody writes to, in a fresh directory: opened as an ordinary file, it waits for a
/// writer for ever.
#[cfg(unix)]
fn fifo(name: &str) -> (tempfile::TempDir, PathBuf) {
    let (dir, path) = temp_path(name);
    let made = Command::new("mkfifo").arg(&path).status().unwrap();
    assert!(made.success(), "mkfifo {}", path.display());
    (dir, path)
}

#[cfg(unix)]
#[test]
fn a_fifo_as_config_is_refused_at_once_by_every_reader() {
    let (_dir, path) = fifo("config.toml");
    let shown = path.display().to_string();
    for args in [
        vec!["--config", &shown, "--arm", "cell3"],
        vec!["arms", "--config", &shown],
        vec!["status", "--config", &shown, "--arm", "cell3"],
        vec!["modbus", "--config", &shown, "--arm", "cell3", "stop"],
    ] {
        let (code, stderr) = run_armjog(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(&shown), "{args:?} names the file: {stderr}");
        assert!(stderr.contains(A_FIFO), "{args:?}: {stderr}");
    }
}

#[cfg(unix)]
#[test]
fn a_fifo_as_keymap_or_book_is_refused_at_once() {
    let (_dir, path) = fifo("keymap.json");
    let shown = path.display().to_string();
    assert_refused(&["--keymap", &shown], &shown, A_FIFO);
    let (_dir, path) = fifo("book.json");
    let shown = path.display().to_string();
    assert_refused(&["--positions", &shown], &shown, A_FIFO);
    // A profile's book alike.
    let (_config_dir, config) = temp_path("config.toml");
    std::fs::write(&config, format!("[arms.bench]\npositions = {shown:?}\n")).unwrap();
    let config = config.display().to_string();
    assert_refused(&["--config", &config, "--arm", "bench"], &shown, A_FIFO);
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
