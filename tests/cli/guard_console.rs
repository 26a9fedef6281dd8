//! The stop guard end to end: the real console binary jogs the in-test simulated arm over
//! Modbus in tmux (`.ci/run` installs it) and is killed with SIGKILL; and the console's state
//! machine and status bar when its guard comes and goes.

use crate::guard_support;

use std::time::Duration;

use tokio::time::Instant;

use armjog::link::interface::{ArmCommand, ArmEvent, GuardStatus};
use guard_support::{
    BIN, Tmux, arm_state, assert_exit, assert_still, log_dir, modbus_addr, pids_with, send_signal,
    simulator, wait_moving,
};

/// The console on the simulator's Modbus port, logs in the test's directory.
fn console_command(addr: &str) -> String {
    format!(
        "exec env ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} {BIN} --modbus {addr} --unit 1 --key-release repeat",
        d = log_dir().display(),
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_guard_exits_when_the_console_quits() {
    let sim = simulator().await;
    let addr = modbus_addr(&sim);
    let tmux = Tmux::start("quit", &console_command(&addr));
    tmux.wait_for(Duration::from_secs(20), "the guard", |s| {
        s.contains("GUARD OK")
    })
    .await;
    let guards = pids_with(&["guard", "--modbus", &addr]);
    assert_eq!(guards.len(), 1, "one guard process runs: {guards:?}");
    tmux.key("q");
    assert_exit(&guards, "with the console").await;
    assert!(!arm_state(&sim).await.0, "nothing moves");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn killing_the_console_with_sigkill_mid_jog_stops_the_arm() {
    let sim = simulator().await;
    let addr = modbus_addr(&sim);
    let tmux = Tmux::start("sigkill", &console_command(&addr));
    tmux.wait_for(Duration::from_secs(20), "the link and the guard", |s| {
        s.contains("LINK UP") && s.contains("GUARD OK")
    })
    .await;
    let console_pid = tmux.pane_pid();
    let guards = pids_with(&["guard", "--modbus", &addr]);
    assert_eq!(guards.len(), 1, "one guard process runs: {guards:?}");

    // 10 % of 250 mm/s: seconds away from any limit.
    tmux.slow_to_10_percent().await;

    // Hold w (tmux has no releases: a press, then a repeat every 30 ms), and kill the console
    // with SIGKILL while the arm moves: no code of the console runs after that.
    let holding = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    let keys = {
        let holding = holding.clone();
        let socket = tmux.socket.clone();
        // Through one control-mode client, not a `tmux send-keys` process per repeat: on a
        // loaded machine those scatter the repeats until the console no longer sees a hold.
        let mut control = std::process::Command::new("tmux")
            .args(["-L", &socket, "-C", "attach-session", "-t", "console"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .expect("tmux control client");
        let mut stdin = control.stdin.take().expect("control client stdin");
        std::thread::spawn(move || {
            use std::io::Write;
            while holding.load(std::sync::atomic::Ordering::Relaxed) {
                let sent = std::time::Instant::now();
                let _ = writeln!(stdin, "send-keys -t console w").and_then(|()| stdin.flush());
                std::thread::sleep(Duration::from_millis(30).saturating_sub(sent.elapsed()));
            }
            // End of input detaches the control client.
            drop(stdin);
            let _ = control.wait();
        })
    };
    let moving = wait_moving(&sim, true, Duration::from_secs(10)).await;
    tokio::time::sleep(Duration::from_millis(300)).await;
    let (still_moving, x_at_kill) = arm_state(&sim).await;
    let killed = send_signal(console_pid, "-9");
    // `kill` has returned: the signal is delivered.
    let killed_at = Instant::now();
    holding.store(false, std::sync::atomic::Ordering::Relaxed);
    assert!(
        moving.is_some() && still_moving,
        "w jogged the arm over Modbus"
    );
    assert!(killed, "kill -9 {console_pid}");

    wait_moving(&sim, false, Duration::from_secs(2))
        .await
        .expect("the guard stops the twist within 2 s of the console's death");
    let took = killed_at.elapsed();
    let (_, x_stopped) = arm_state(&sim).await;
    let _ = keys.join();
    eprintln!(
        "console SIGKILLed -> arm stopped in {:.1} ms ({x_at_kill:.1} -> {x_stopped:.1} mm)",
        took.as_secs_f64() * 1000.0
    );
    assert_still(&sim).await;

    // Its work done, the guard exits.
    assert_exit(&guards, "after the stop").await;
}

/// The status bar's two lines as text, 80 columns wide.
fn status_text(app: &armjog::console::app::App) -> (String, ratatui::buffer::Buffer) {
    use armjog::console::ui::{Theme, status};
    use armjog::console::view::View;
    let mut terminal =
        ratatui::Terminal::new(ratatui::backend::TestBackend::new(80, 2)).expect("terminal");
    terminal
        .draw(|f| status::draw(f, f.area(), &View::new(app), &Theme { color: true }))
        .expect("draw");
    let buffer = terminal.backend().buffer().clone();
    let text: String = buffer.content().iter().map(|c| c.symbol()).collect();
    (text, buffer)
}

#[test]
fn the_console_stops_and_says_so_when_its_guard_goes_down_and_shows_its_state() {
    use armjog::console::app::{App, AppConfig, Effect, Input, KeyInput, Severity};
    use armjog::console::jog::{KeyKind, ReleaseMode};
    use armjog::console::keymap::Keymap;
    use armjog::console::positions::PositionBook;
    use armjog::console::ui::Theme;
    use armjog::link::interface::LinkStatus;

    let t0 = std::time::Instant::now();
    let mut app = App::new(
        AppConfig {
            keymap: Keymap::builtin("default").expect("keymap").into(),
            release_mode: ReleaseMode::Reported,
            refresh: Duration::from_millis(100),
            positions_on_operator: false,
            max_jog_speed: 0.25,
            joint_jog_speed: armjog::link::driver::JOINT_JOG_SPEED,
            frames: true,
            simulated: false,
            arm_name: None,
            home_action: None,
            fence: None,

            config_file: None,

            new_profile: Vec::new(),

            recording_off: false,
        },
        PositionBook::new(),
    );
    let up = LinkStatus::Up {
        description: "modbus 10.0.0.9:502 unit 1".into(),
    };
    app.handle(Input::Arm(ArmEvent::Status(up)), t0);
    let (text, _) = status_text(&app);
    assert!(
        !text.contains("GUARD"),
        "no badge while none is required: {text}"
    );

    app.handle(Input::Arm(ArmEvent::Guard(GuardStatus::Starting)), t0);
    let (text, buffer) = status_text(&app);
    assert!(text.contains("NO GUARD"), "{text}");
    let at = text.find("NO GUARD").expect("badge");
    assert_eq!(
        buffer.content()[at + 1].style().bg,
        Theme { color: true }.alarm().bg
    );

    app.handle(
        Input::Arm(ArmEvent::Guard(GuardStatus::Ready { pid: 42 })),
        t0,
    );
    assert!(status_text(&app).0.contains("GUARD OK"));
    let w = KeyInput {
        key: "w".parse().expect("key"),
        text: Some('w'),
        kind: KeyKind::Press,
    };
    let effects = app.handle(Input::Key(w), t0);
    assert!(
        effects
            .iter()
            .any(|e| matches!(e, Effect::Arm(ArmCommand::Jog(_)))),
        "w jogs with the guard ready: {effects:?}"
    );

    // The guard dies with w still held: the console stops, forgets the key, says why.
    let down = GuardStatus::Down {
        reason: "the stop guard 42 exited (signal: 9)".into(),
    };
    let t1 = t0 + Duration::from_millis(50);
    let effects = app.handle(Input::Arm(ArmEvent::Guard(down)), t1);
    assert!(
        effects.contains(&Effect::Arm(ArmCommand::Stop)),
        "stopped: {effects:?}"
    );
    assert!(app.jog().active().is_none(), "nothing held any more");
    let (message, severity) = app.message().expect("a message");
    assert_eq!(severity, Severity::Error);
    assert!(
        message.contains("stop guard down") && message.contains("exited"),
        "{message}"
    );
    assert!(status_text(&app).0.contains("NO GUARD"));

    // Back again: nothing restarts without a fresh press.
    let t2 = t1 + Duration::from_millis(500);
    let effects = app.handle(
        Input::Arm(ArmEvent::Guard(GuardStatus::Ready { pid: 43 })),
        t2,
    );
    let effects_later = app.handle(Input::Tick, t2 + Duration::from_millis(200));
    assert!(
        !effects
            .iter()
            .chain(&effects_later)
            .any(|e| matches!(e, Effect::Arm(ArmCommand::Jog(_)))),
        "no jog after the guard is back: {effects:?} {effects_later:?}"
    );
}
