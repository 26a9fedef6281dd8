//! `armjog replay --events`: a recording made by the recorder printed one event a line, as JSON
//! with `--json`; a file cut short read up to its last good message and said so; a file that is
//! not a recording refused with its name.

use armjog::console::app::{Input, KeyInput, Severity};
use armjog::console::jog::{JogMotion, KeyKind};
use armjog::console::recorder::{QUEUE, Recorder};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};

use crate::armjog_run::armjog;

/// A short session recorded into `dir`: the link up, w pressed, a jog, released, a stop, a
/// refusal said.
fn session(dir: &std::path::Path) -> std::path::PathBuf {
    let path = dir.join("armjog-2026-12-06T18-00-00Z-sim.mcap");
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    let up = LinkStatus::Up {
        description: "talos 127.0.0.1:61616".into(),
    };
    recorder.input(&Input::Arm(ArmEvent::Status(up)));
    let key = |kind| {
        Input::Key(KeyInput {
            key: "w".parse().expect("w"),
            text: Some('w'),
            kind,
        })
    };
    recorder.input(&key(KeyKind::Press));
    recorder.command(&ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }));
    recorder.input(&key(KeyKind::Release));
    recorder.command(&ArmCommand::Stop);
    recorder.said(Some((
        "refused: the arm reports in fault",
        Severity::Warning,
    )));
    drop(recorder);
    path
}

/// A line's text after its time (`2026-12-06 19:08:46.987 UTC  `).
fn after_time(line: &str) -> &str {
    line.split_once(" UTC  ").map_or(line, |(_, event)| event)
}

#[tokio::test]
async fn the_events_print_one_a_line_in_order() {
    let dir = tempfile::tempdir().expect("a folder");
    let file = session(dir.path());
    let run = armjog(&["replay", "--events", file.to_str().expect("utf-8")]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    let events: Vec<&str> = run.stdout.lines().map(after_time).collect();
    assert_eq!(
        events,
        [
            "info     link up: talos 127.0.0.1:61616",
            "key      w press",
            "command  jog (+X)",
            "key      w release",
            "command  stop",
            "warning  refused: the arm reports in fault",
        ]
    );
    assert_eq!(run.stderr, "");
    let json = armjog(&[
        "replay",
        "--events",
        "--json",
        file.to_str().expect("utf-8"),
    ])
    .await;
    let first: serde_json::Value =
        serde_json::from_str(json.stdout.lines().nth(1).expect("a second line")).expect("JSON");
    assert_eq!(
        (first["topic"].as_str(), first["kind"].as_str()),
        (Some("/keys"), Some("press"))
    );
}

#[tokio::test]
async fn a_file_cut_short_is_read_up_to_its_last_good_message_and_says_so() {
    let dir = tempfile::tempdir().expect("a folder");
    let file = session(dir.path());
    let bytes = std::fs::read(&file).expect("read");
    let cut = dir.path().join("cut.mcap");
    // Half the file: the end (summary, footer) gone, and the data part-way through.
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("written");
    let run = armjog(&["replay", "--events", cut.to_str().expect("utf-8")]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stderr.contains("read up to its last good message"),
        "{}",
        run.stderr
    );
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
}

#[tokio::test]
async fn a_file_that_is_not_a_recording_is_refused_with_its_name() {
    let dir = tempfile::tempdir().expect("a folder");
    let foreign = dir.path().join("notes.mcap");
    std::fs::write(&foreign, "not an mcap file\n").expect("written");
    let run = armjog(&["replay", "--events", foreign.to_str().expect("utf-8")]).await;
    assert_eq!(run.code, 1);
    assert!(
        run.stderr.contains("notes.mcap: not an MCAP recording"),
        "{}",
        run.stderr
    );
    // Playback refuses it the same way, before it takes the terminal.
    let bare = armjog(&["replay", foreign.to_str().expect("utf-8")]).await;
    assert_eq!(bare.code, 1);
    assert!(
        bare.stderr.contains("notes.mcap: not an MCAP recording"),
        "{}",
        bare.stderr
    );
    let missing = dir.path().join("gone.mcap");
    let gone = armjog(&["replay", missing.to_str().expect("utf-8")]).await;
    assert_eq!(gone.code, 1);
    assert!(
        gone.stderr.contains("gone.mcap: cannot read it"),
        "{}",
        gone.stderr
    );
}
