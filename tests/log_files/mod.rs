//! The log files a run writes: `PREFIX.YYYY-MM-DD.log`, one per program and UTC day (a run over
//! midnight writes two), as `armjog::logging` names them; spelt out here by hand.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// Whether `name` is one of `prefix`'s daily files: `armjog-cli.2026-12-01.log` for
/// `armjog-cli`.
pub fn is_daily_log(name: &str, prefix: &str) -> bool {
    let Some(date) = name
        .strip_prefix(prefix)
        .and_then(|rest| rest.strip_prefix('.'))
        .and_then(|rest| rest.strip_suffix(".log"))
    else {
        return false;
    };
    let digits = |s: &str, n: usize| s.len() == n && s.bytes().all(|b| b.is_ascii_digit());
    let parts: Vec<&str> = date.split('-').collect();
    parts.len() == 3 && digits(parts[0], 4) && digits(parts[1], 2) && digits(parts[2], 2)
}

/// `prefix`'s log files in `dir`, oldest day first.
pub fn daily_logs(dir: &Path, prefix: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.file_name()
                        .and_then(|n| n.to_str())
                        .is_some_and(|n| is_daily_log(n, prefix))
                })
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    files
}

/// What `prefix`'s log files in `dir` hold, oldest day first; empty when there is none yet.
pub fn read_logs(dir: &Path, prefix: &str) -> String {
    daily_logs(dir, prefix)
        .iter()
        .map(|f| std::fs::read_to_string(f).unwrap_or_default())
        .collect()
}

/// Like [`read_logs`], but fails when `dir` holds no file of `prefix`.
pub fn read_existing_logs(dir: &Path, prefix: &str) -> String {
    assert!(
        !daily_logs(dir, prefix).is_empty(),
        "no {prefix}.YYYY-MM-DD.log in {}",
        dir.display()
    );
    read_logs(dir, prefix)
}

#[test]
fn daily_names_are_recognised_and_others_are_not() {
    assert!(is_daily_log("armjog-cli.2026-12-01.log", "armjog-cli"));
    for other in [
        "armjog-cli.log",
        "armjog-console.2026-12-01.log",
        "armjog-cli.2026-12-1.log",
        "armjog-cli.2026-12-01.log.1",
        "audit-2026-12-01.jsonl",
    ] {
        assert!(!is_daily_log(other, "armjog-cli"), "{other}");
    }
}
