//! The session around the app: an input's commands recorded at the loop's next turn, stamped
//! when it was handled, needing no app by then, kept in the order of their inputs, written
//! even when the session is dropped; a save over Talos with Modbus telemetry.

use super::*;

/// Every line written in `dir`, whatever its day's file, oldest file first.
fn all_lines(dir: &std::path::Path) -> Vec<String> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|entry| entry.expect("entry").path())
        .collect();
    files.sort();
    files
        .iter()
        .flat_map(|file| {
            let text = std::fs::read_to_string(file).expect("audit file");
            text.lines().map(str::to_string).collect::<Vec<_>>()
        })
        .collect()
}

/// An app on `book` and an audit session writing to `dir`.
fn app_and_session(
    dir: &std::path::Path,
    book: PositionBook,
) -> (crate::console::app::App, AuditSession) {
    let config = crate::console::app::AppConfig::for_tests();
    let app = crate::console::app::App::new(config.clone(), book);
    let session = AuditSession::start(&config, "sim".into(), None, Some(dir.into()), None);
    (app, session)
}

#[tokio::test]
async fn an_inputs_commands_are_recorded_at_the_next_turn_stamped_when_it_was_handled() {
    let dir = temp_dir();
    let (app, mut session) = app_and_session(dir.path(), PositionBook::new());
    session.command(ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }));
    let before = SystemTime::now();
    session.handled(&app);
    let after = SystemTime::now();
    // The loop's next turn comes later: the record keeps the input's time.
    std::thread::sleep(Duration::from_millis(50));
    session.record_handled();
    // Recorded once, however many turns follow.
    session.record_handled();
    session.finish(Duration::from_secs(10)).await;
    let lines = all_lines(dir.path());
    let event = |line: &String| {
        let value: serde_json::Value = serde_json::from_str(line).expect("json");
        (
            value["event"].as_str().map(str::to_string),
            value["ts"].clone(),
        )
    };
    let events: Vec<_> = lines.iter().map(event).collect();
    let names: Vec<_> = events.iter().map(|(name, _)| name.as_deref()).collect();
    assert_eq!(
        names,
        [
            Some("session_start"),
            Some("jog_start"),
            Some("session_end")
        ],
        "{lines:?}"
    );
    // The same format, so the strings order as the times do.
    let stamped = events[1].1.as_str().expect("ts").to_string();
    let (earliest, latest) = (utc::rfc3339_ms(before), utc::rfc3339_ms(after));
    assert!(
        earliest <= stamped && stamped <= latest,
        "jog_start at {stamped}, handled between {earliest} and {latest}"
    );
}

fn event_names(dir: &std::path::Path) -> Vec<String> {
    all_lines(dir)
        .iter()
        .map(|line| {
            let value: serde_json::Value = serde_json::from_str(line).expect("json");
            value["event"].as_str().unwrap_or_default().to_string()
        })
        .collect()
}

#[tokio::test]
async fn an_inputs_records_need_no_app_once_it_is_handled() {
    let dir = temp_dir();
    let mut book = PositionBook::new();
    book.get_or_insert("pick").cartesian = Some([4566, -10, 4338]);
    let (app, mut session) = app_and_session(dir.path(), book);
    let pose = pick_pose();
    session.command(ArmCommand::MoveToPose(pose));
    session.handled(&app);
    drop(app);
    // The app is gone (a panic unwound it): the go-to is still recorded, with its name.
    session.record_handled();
    session.finish(Duration::from_secs(10)).await;
    let lines = all_lines(dir.path());
    let go_to: Vec<serde_json::Value> = lines
        .iter()
        .map(|line| serde_json::from_str(line).expect("json"))
        .filter(|value: &serde_json::Value| value["event"] == "go_to")
        .collect();
    assert_eq!(go_to.len(), 1, "{lines:?}");
    assert_eq!(go_to[0]["name"], "pick", "{lines:?}");
}

#[test]
fn a_session_dropped_between_an_input_and_the_next_turn_records_the_input() {
    let dir = temp_dir();
    let (app, mut session) = app_and_session(dir.path(), PositionBook::new());
    session.command(ArmCommand::Jog(JogMotion::Cartesian { x: 0, y: 1, z: 0 }));
    session.handled(&app);
    // As an unwinding panic drops it: no next turn, no finish.
    drop(session);
    // The writer ends once it has written what it was handed.
    let until = std::time::Instant::now() + Duration::from_secs(10);
    let mut names = event_names(dir.path());
    while !names.iter().any(|name| name == "jog_start") && std::time::Instant::now() < until {
        std::thread::sleep(Duration::from_millis(20));
        names = event_names(dir.path());
    }
    assert_eq!(names, ["session_start", "jog_start"]);
}

#[tokio::test]
async fn records_keep_the_order_of_their_inputs_whenever_they_are_made() {
    let dir = temp_dir();
    let (app, mut session) = app_and_session(dir.path(), PositionBook::new());
    // A press, then its release before the loop turned again (a key's records wait until
    // its frames are out): the press is recorded first.
    session.command(ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }));
    session.handled(&app);
    session.command(ArmCommand::Stop);
    session.handled(&app);
    // An arm event after: recorded after both.
    session.input(&crate::console::app::Input::Arm(ArmEvent::Status(
        LinkStatus::Up {
            description: "talos 10.0.0.2:61616".into(),
        },
    )));
    session.finish(Duration::from_secs(10)).await;
    assert_eq!(
        event_names(dir.path()),
        [
            "session_start",
            "jog_start",
            "jog_stop",
            "link_up",
            "session_end"
        ]
    );
}

/// A key press, as the terminal reader hands it to the app.
fn key_press(name: &str) -> crate::console::app::Input {
    use crate::console::app::{Input, KeyInput};
    let key = name.parse().expect("key name");
    let text = name.chars().next().filter(|_| name.chars().count() == 1);
    Input::Key(KeyInput {
        key,
        text,
        kind: crate::console::jog::KeyKind::Press,
    })
}

#[tokio::test]
async fn a_save_over_talos_with_modbus_telemetry_records_the_tools_position() {
    use crate::console::app::{Effect, Input};
    use crate::link::interface::TelemetrySource;
    let dir = temp_dir();
    // A Talos operator in the ICD dialect keeps the positions; Modbus gives the telemetry.
    let (mut app, mut session) = app_and_session(dir.path(), PositionBook::new());
    let now = std::time::Instant::now();
    let inputs = [
        Input::Arm(ArmEvent::TelemetrySource(TelemetrySource::Modbus)),
        Input::Arm(ArmEvent::Status(LinkStatus::Up {
            description: "talos 127.0.0.1:61616, modbus 127.0.0.1:502".into(),
        })),
        Input::Arm(telemetry_at(pick_pose())),
    ];
    for input in inputs {
        session.input(&input);
        app.handle(input, now);
        session.handled(&app);
    }
    let keys = ["p", "b", "e", "n", "c", "h", "enter"];
    for name in keys {
        let input = key_press(name);
        session.input(&input);
        for effect in app.handle(input, now) {
            if let Effect::Arm(command) = effect {
                session.command(command);
            }
        }
        session.handled(&app);
    }
    session.finish(Duration::from_secs(10)).await;
    let saves: Vec<String> = all_lines(dir.path())
        .into_iter()
        .filter(|line| line.contains(r#""event":"save""#))
        .collect();
    assert_eq!(saves.len(), 1, "{saves:?}");
    assert!(
        saves[0].ends_with(r#""event":"save","name":"bench","position_mm":[456.6,-1.0,433.8]}"#),
        "{saves:?}"
    );
}
