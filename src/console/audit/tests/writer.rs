//! The writer: one file per UTC day (a session over midnight goes on in the next), lines
//! appended, records held until handed over or the log dropped and none lost, a failed write
//! reported once and stopping nothing.

use super::*;

/// Writes `records` through the writer thread, waits for it to end, and returns the failures
/// it reported.
async fn write_records(dir: std::path::PathBuf, records: Vec<AuditRecord>) -> Vec<String> {
    let mut log = AuditLog::start(Some(dir));
    for record in records {
        log.record(record);
    }
    let (_, closed) = tokio::sync::mpsc::unbounded_channel();
    let mut reported = std::mem::replace(&mut log.errors, closed);
    log.finish(Duration::from_secs(10)).await;
    let mut errors = Vec::new();
    while let Ok(e) = reported.try_recv() {
        errors.push(e);
    }
    errors
}

#[tokio::test]
async fn a_session_over_midnight_continues_in_the_next_days_file() {
    let dir = temp_dir();
    // 2026-11-30T23:59:59.900Z, then 200 ms later.
    let before = UNIX_EPOCH + Duration::from_millis(1_796_083_199_900);
    let after = before + Duration::from_millis(200);
    let errors = write_records(
        dir.path().to_path_buf(),
        vec![
            AuditRecord::new(before, AuditEvent::QuickStop),
            AuditRecord::new(after, AuditEvent::FaultReset),
        ],
    )
    .await;
    assert!(errors.is_empty(), "{errors:?}");
    let read = |name: &str| std::fs::read_to_string(dir.path().join(name)).expect(name);
    assert_eq!(
        read("audit-2026-11-30.jsonl"),
        "{\"ts\":\"2026-11-30T23:59:59.900Z\",\"event\":\"quick_stop\"}\n"
    );
    assert_eq!(
        read("audit-2026-12-01.jsonl"),
        "{\"ts\":\"2026-12-01T00:00:00.100Z\",\"event\":\"fault_reset\"}\n"
    );
}

#[tokio::test]
async fn lines_are_appended_to_an_existing_file() {
    let dir = temp_dir();
    let path = dir.path().join("audit-2026-11-30.jsonl");
    std::fs::write(&path, "earlier\n").expect("seed");
    write_records(
        dir.path().to_path_buf(),
        vec![AuditRecord::new(t0(), AuditEvent::Stop)],
    )
    .await;
    let text = std::fs::read_to_string(&path).expect("read");
    assert_eq!(
        text,
        "earlier\n{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"stop\"}\n"
    );
}

/// The lines of `name` in `dir` once the writer has written `count` of them (at most 10 s).
fn lines_once_written(dir: &std::path::Path, name: &str, count: usize) -> Vec<String> {
    let until = std::time::Instant::now() + Duration::from_secs(10);
    loop {
        let text = std::fs::read_to_string(dir.join(name)).unwrap_or_default();
        let lines: Vec<String> = text.lines().map(str::to_string).collect();
        if lines.len() >= count || std::time::Instant::now() >= until {
            return lines;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[tokio::test]
async fn records_are_held_until_handed_over_and_none_is_lost() {
    let dir = temp_dir();
    let mut log = AuditLog::start(Some(dir.path().to_path_buf()));
    assert_eq!(log.hand_over_at(), None, "nothing held yet");
    let before = std::time::Instant::now();
    log.record(AuditRecord::new(t0(), AuditEvent::Stop));
    let due = log.hand_over_at().expect("a record is held");
    assert!(due >= before + HAND_OVER_AFTER, "{due:?}");
    assert!(
        due <= std::time::Instant::now() + HAND_OVER_AFTER,
        "{due:?}"
    );
    // A second record is due with the first, not later.
    log.record(AuditRecord::new(t0(), AuditEvent::QuickStop));
    assert_eq!(log.hand_over_at(), Some(due));
    // The writer has not been given them: nothing is written however long it waits.
    std::thread::sleep(Duration::from_millis(100));
    assert!(!dir.path().join("audit-2026-11-30.jsonl").exists());
    log.hand_over();
    assert_eq!(log.hand_over_at(), None);
    let lines = lines_once_written(dir.path(), "audit-2026-11-30.jsonl", 2);
    assert_eq!(
        lines,
        [
            "{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"stop\"}",
            "{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"quick_stop\"}",
        ]
    );
    log.finish(Duration::from_secs(10)).await;
}

#[test]
fn records_held_when_the_log_is_dropped_are_written() {
    // As when a panic unwinds through the event loop.
    let dir = temp_dir();
    let mut log = AuditLog::start(Some(dir.path().to_path_buf()));
    log.record(AuditRecord::new(t0(), AuditEvent::FaultReset));
    drop(log);
    let lines = lines_once_written(dir.path(), "audit-2026-11-30.jsonl", 1);
    assert_eq!(
        lines,
        ["{\"ts\":\"2026-11-30T22:27:31.853Z\",\"event\":\"fault_reset\"}"]
    );
}

#[tokio::test]
async fn a_write_that_fails_is_reported_once_and_stops_nothing() {
    let dir = temp_dir();
    // A file where the directory should be: unwritable even for root (unlike a read-only
    // directory).
    let blocked = dir.path().join("not-a-dir");
    std::fs::write(&blocked, "").expect("seed");
    let records = (0..5)
        .map(|i| AuditRecord::new(t0() + Duration::from_secs(i), AuditEvent::Stop))
        .collect();
    let started = std::time::Instant::now();
    let errors = write_records(blocked.join("audit"), records).await;
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains("audit log not written") && errors[0].contains("not-a-dir"),
        "{}",
        errors[0]
    );
    assert!(started.elapsed() < Duration::from_secs(10));
}
