//! The stop guard: a dead or frozen console cannot leave a Modbus twist running.
//!
//! The simulated arm runs in the test (its Modbus twist, like a real Kinova's, has no
//! watchdog); the guard is the real binary (`armjog guard`), fed through a pipe the test holds
//! like a console would. The last test kills the real console binary with SIGKILL mid-jog in
//! tmux (`.ci/run` installs it). Bounds are generous for a loaded CI; the design target of
//! 300 ms from the console's death to the stop is logged, not asserted.

use std::process::Stdio;
use std::time::Duration;

use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader, Lines};
use tokio::process::{Child, ChildStdin, ChildStdout, Command};
use tokio::sync::mpsc::UnboundedReceiver;
use tokio::time::Instant;

use armjog::kortex::{ReferenceFrame, Twist};
use armjog::link::arm::{ArmCommand, ArmEvent, GuardStatus};
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::guard::GuardPolicy;
use armjog::link::{ModbusConfig, ModbusLink};
use armjog::sim::{SimConfig, Simulator};

const BIN: &str = env!("CARGO_BIN_EXE_armjog");

async fn simulator() -> Simulator {
    Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator")
}

fn modbus_addr(sim: &Simulator) -> String {
    sim.modbus_addr
        .expect("the simulator serves Modbus")
        .to_string()
}

fn log_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("armjog-guard-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Whether the simulated arm moves, and its tool x in mm.
async fn arm_state(sim: &Simulator) -> (bool, f64) {
    sim.arm
        .with(|arm, _| (arm.is_moving(), arm.pose().position.x * 1000.0))
        .await
        .expect("simulated arm")
}

/// Polls until the arm's motion is `moving`; returns how long it took, or `None` after `within`.
async fn wait_moving(sim: &Simulator, moving: bool, within: Duration) -> Option<Duration> {
    let started = Instant::now();
    while started.elapsed() < within {
        if arm_state(sim).await.0 == moving {
            return Some(started.elapsed());
        }
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
    None
}

/// Asserts the tool stays where it is for a while (the stop held, nothing restarted it).
async fn assert_still(sim: &Simulator) {
    let (_, x0) = arm_state(sim).await;
    tokio::time::sleep(Duration::from_millis(400)).await;
    let (moving, x1) = arm_state(sim).await;
    assert!(
        !moving && (x1 - x0).abs() < 0.05,
        "the arm keeps still: {x0:.3} -> {x1:.3} mm"
    );
}

/// A client standing in for the console's twist: 20 mm/s +X, far from any limit for seconds.
async fn start_twist(sim: &Simulator) -> ModbusLink {
    let mut config = ModbusConfig::new(modbus_addr(sim));
    config.poll_rate_hz = None;
    config.twist_hold = None;
    let (link, _events) = ModbusLink::connect(config).await.expect("connect");
    let twist = Twist {
        x: 0.02,
        ..Twist::default()
    };
    link.jog_twist(ReferenceFrame::Base, twist)
        .await
        .expect("twist");
    assert!(
        wait_moving(sim, true, Duration::from_secs(5))
            .await
            .is_some(),
        "the twist runs"
    );
    link
}

/// The guard process, with the pipe a console would hold.
struct Guard {
    child: Child,
    stdin: Option<ChildStdin>,
    lines: Lines<BufReader<ChildStdout>>,
}

impl Guard {
    async fn start(sim: &Simulator) -> Guard {
        let mut child = Command::new(BIN)
            .args(["guard", "--modbus", &modbus_addr(sim), "--unit", "1"])
            .env("ARMJOG_LOG_DIR", log_dir())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .kill_on_drop(true)
            .spawn()
            .expect("start armjog guard");
        let stdin = child.stdin.take();
        let lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
        let mut guard = Guard {
            child,
            stdin,
            lines,
        };
        let ready = guard.line(Duration::from_secs(10)).await;
        assert_eq!(
            ready.as_deref(),
            Some("ready"),
            "the guard says it is ready"
        );
        guard
    }

    async fn beat(&mut self) {
        let stdin = self.stdin.as_mut().expect("pipe open");
        stdin.write_all(b".").await.expect("heartbeat");
        stdin.flush().await.expect("heartbeat");
    }

    /// Heartbeats every 100 ms for `duration`.
    async fn beat_for(&mut self, duration: Duration) {
        let until = Instant::now() + duration;
        while Instant::now() < until {
            self.beat().await;
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }

    /// The next line other than the guard's periodic `alive`.
    async fn line(&mut self, within: Duration) -> Option<String> {
        let until = Instant::now() + within;
        loop {
            let line = tokio::time::timeout_at(until, self.lines.next_line())
                .await
                .ok()
                .and_then(|l| l.ok())
                .flatten()?;
            if line != "alive" {
                return Some(line);
            }
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_guard_stops_a_running_twist_when_the_console_pipe_closes() {
    let sim = simulator().await;
    let mut guard = Guard::start(&sim).await;
    guard.beat().await;
    let _console_link = start_twist(&sim).await;
    guard.beat_for(Duration::from_millis(300)).await;
    assert!(
        arm_state(&sim).await.0,
        "still moving with the console alive"
    );

    // The console dies: its end of the pipe closes.
    drop(guard.stdin.take());
    let took = wait_moving(&sim, false, Duration::from_secs(2))
        .await
        .expect("the guard stops the twist within 2 s of the pipe closing");
    eprintln!(
        "pipe closed -> arm stopped in {:.1} ms",
        took.as_secs_f64() * 1000.0
    );
    assert_still(&sim).await;

    let said = guard.line(Duration::from_secs(5)).await.unwrap_or_default();
    assert!(
        said.starts_with("stopped the console is gone"),
        "the guard reports its stop: {said:?}"
    );
    let status = tokio::time::timeout(Duration::from_secs(5), guard.child.wait())
        .await
        .expect("the guard exits after the stop")
        .expect("exit status");
    assert!(status.success(), "exit status {status}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_silent_console_gets_its_twist_stopped_and_the_guard_keeps_watching() {
    let sim = simulator().await;
    let mut guard = Guard::start(&sim).await;
    guard.beat().await;
    let console_link = start_twist(&sim).await;

    // The pipe stays open but no heartbeat comes: a frozen console.
    let took = wait_moving(&sim, false, Duration::from_secs(4))
        .await
        .expect("the guard stops the twist after the heartbeat timeout (1 s)");
    eprintln!(
        "heartbeat lost -> arm stopped after {:.0} ms",
        took.as_secs_f64() * 1000.0
    );
    let said = guard.line(Duration::from_secs(5)).await.unwrap_or_default();
    assert!(
        said.starts_with("stopped no heartbeat"),
        "the guard reports why: {said:?}"
    );
    assert!(
        guard.child.try_wait().expect("guard status").is_none(),
        "the guard keeps watching"
    );

    // The console is back: a fresh twist runs while it beats, and the guard leaves it alone.
    console_link.stop().await.expect("stop");
    guard.beat().await;
    let twist = Twist {
        x: -0.02,
        ..Twist::default()
    };
    console_link
        .jog_twist(ReferenceFrame::Base, twist)
        .await
        .expect("twist");
    guard.beat_for(Duration::from_millis(1500)).await;
    assert!(arm_state(&sim).await.0, "a beating console keeps its twist");

    drop(guard.stdin.take());
    wait_moving(&sim, false, Duration::from_secs(2))
        .await
        .expect("stopped when the pipe closes");
}

/// Drives the driver's events until `done` matches one; panics after `within`.
async fn wait_event(
    events: &mut UnboundedReceiver<ArmEvent>,
    within: Duration,
    what: &str,
    mut done: impl FnMut(&ArmEvent) -> bool,
) -> ArmEvent {
    let until = Instant::now() + within;
    loop {
        let event = tokio::time::timeout_at(until, events.recv())
            .await
            .unwrap_or_else(|_| panic!("waited {within:?} for {what}"))
            .expect("driver alive");
        if done(&event) {
            return event;
        }
    }
}

fn jog_x() -> ArmCommand {
    ArmCommand::Jog(armjog::console::jog::JogMotion::Cartesian { x: 1, y: 0, z: 0 })
}

fn modbus_driver(sim: &Simulator, guard: GuardPolicy) -> (Driver, UnboundedReceiver<ArmEvent>) {
    let mut config = DriverConfig::new(None, Some(ModbusConfig::new(modbus_addr(sim))));
    config.guard = guard;
    // Slow enough to stay far from any limit for the whole test.
    config.max_jog_speed = 0.04;
    Driver::spawn(config)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_console_refuses_modbus_jogs_when_its_guard_cannot_start() {
    let sim = simulator().await;
    let missing = std::path::PathBuf::from("/nonexistent/armjog-guard");
    let (driver, mut events) = modbus_driver(&sim, GuardPolicy::Spawn(missing));
    let down = wait_event(
        &mut events,
        Duration::from_secs(10),
        "the guard down",
        |e| matches!(e, ArmEvent::Guard(GuardStatus::Down { .. })),
    )
    .await;
    let ArmEvent::Guard(GuardStatus::Down { reason }) = down else {
        unreachable!()
    };
    assert!(
        reason.contains("cannot start the stop guard /nonexistent/armjog-guard"),
        "names the program: {reason}"
    );

    assert!(driver.send(jog_x()));
    let failed = wait_event(
        &mut events,
        Duration::from_secs(5),
        "the jog refused",
        |e| matches!(e, ArmEvent::Failed { command: "jog", .. }),
    )
    .await;
    let ArmEvent::Failed { reason, .. } = failed else {
        unreachable!()
    };
    assert!(
        reason.starts_with("stop guard not running:"),
        "says why: {reason}"
    );
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(!arm_state(&sim).await.0, "nothing moved");
    // Home is motion too.
    assert!(driver.send(ArmCommand::Home));
    wait_event(&mut events, Duration::from_secs(5), "home refused", |e| {
        matches!(e, ArmEvent::Failed { command: "home", reason } if reason.contains("stop guard"))
    })
    .await;
    driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_killed_guard_stops_the_jog_and_is_restarted() {
    let sim = simulator().await;
    let (driver, mut events) = modbus_driver(&sim, GuardPolicy::Spawn(BIN.into()));
    let ready = |e: &ArmEvent| matches!(e, ArmEvent::Guard(GuardStatus::Ready { .. }));
    let ArmEvent::Guard(GuardStatus::Ready { pid }) = wait_event(
        &mut events,
        Duration::from_secs(10),
        "the guard ready",
        ready,
    )
    .await
    else {
        unreachable!()
    };

    // A held key: the jog is re-sent every 100 ms.
    let jogging = {
        let driver = driver.clone();
        tokio::spawn(async move {
            while driver.send(jog_x()) {
                tokio::time::sleep(Duration::from_millis(100)).await;
            }
        })
    };
    assert!(
        wait_moving(&sim, true, Duration::from_secs(5))
            .await
            .is_some(),
        "jogs over Modbus with a guard"
    );

    let killed = std::process::Command::new("kill")
        .args(["-9", &pid.to_string()])
        .status()
        .expect("kill");
    assert!(killed.success());
    wait_event(&mut events, Duration::from_secs(5), "the guard down", |e| {
        matches!(e, ArmEvent::Guard(GuardStatus::Down { .. }))
    })
    .await;
    // The jog goes on being re-sent, but the driver refuses it and stopped the arm.
    wait_moving(&sim, false, Duration::from_secs(3))
        .await
        .expect("the arm stops when its guard dies");
    let ArmEvent::Guard(GuardStatus::Ready { pid: again }) =
        wait_event(&mut events, Duration::from_secs(15), "a new guard", ready).await
    else {
        unreachable!()
    };
    assert_ne!(again, pid, "a fresh guard process");
    jogging.abort();
    driver.send(ArmCommand::Stop);
    driver.shutdown().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_guard_that_stops_answering_is_replaced() {
    let sim = simulator().await;
    let (driver, mut events) = modbus_driver(&sim, GuardPolicy::Spawn(BIN.into()));
    let ready = |e: &ArmEvent| matches!(e, ArmEvent::Guard(GuardStatus::Ready { .. }));
    let ArmEvent::Guard(GuardStatus::Ready { pid }) = wait_event(
        &mut events,
        Duration::from_secs(10),
        "the guard ready",
        ready,
    )
    .await
    else {
        unreachable!()
    };
    // A frozen guard: alive as a process, but it would not stop anything.
    let frozen = std::process::Command::new("kill")
        .args(["-STOP", &pid.to_string()])
        .status()
        .expect("kill");
    assert!(frozen.success());
    let down = wait_event(
        &mut events,
        Duration::from_secs(15),
        "the guard down",
        |e| matches!(e, ArmEvent::Guard(GuardStatus::Down { .. })),
    )
    .await;
    assert!(
        matches!(&down, ArmEvent::Guard(GuardStatus::Down { reason }) if reason.contains("stopped answering")),
        "says why: {down:?}"
    );
    assert!(driver.send(jog_x()));
    wait_event(&mut events, Duration::from_secs(5), "the jog refused", |e| {
        matches!(e, ArmEvent::Failed { command: "jog", reason } if reason.contains("stop guard not running"))
    })
    .await;
    let ArmEvent::Guard(GuardStatus::Ready { pid: again }) =
        wait_event(&mut events, Duration::from_secs(15), "a new guard", ready).await
    else {
        unreachable!()
    };
    assert_ne!(again, pid, "a fresh guard process");
    let until = Instant::now() + Duration::from_secs(5);
    while std::path::Path::new(&format!("/proc/{pid}")).exists() && Instant::now() < until {
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    assert!(
        !std::path::Path::new(&format!("/proc/{pid}")).exists(),
        "the frozen guard was ended"
    );
    driver.shutdown().await;
}

/// A tmux server of our own for the real console, killed on drop.
struct Tmux {
    socket: String,
}

impl Tmux {
    fn start(command: &str) -> Tmux {
        let socket = format!("armjog-guard-test-{}", std::process::id());
        let status = std::process::Command::new("tmux")
            .args(["-L", &socket, "new-session", "-d", "-s", "console"])
            .args(["-x", "100", "-y", "30", command])
            .status()
            .expect("tmux must be installed (apt-get install -y tmux)");
        assert!(status.success(), "tmux new-session failed");
        Tmux { socket }
    }

    fn tmux(&self, args: &[&str]) -> std::process::Output {
        std::process::Command::new("tmux")
            .args(["-L", &self.socket])
            .args(args)
            .output()
            .expect("tmux")
    }

    fn key(&self, key: &str) -> bool {
        self.tmux(&["send-keys", "-t", "console", key])
            .status
            .success()
    }

    fn screen(&self) -> String {
        let out = self.tmux(&["capture-pane", "-p", "-t", "console"]);
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    fn pane_pid(&self) -> u32 {
        let out = self.tmux(&["display-message", "-p", "-t", "console", "#{pane_pid}"]);
        let text = String::from_utf8_lossy(&out.stdout);
        text.trim().parse().expect("pane pid")
    }

    async fn wait_for(&self, within: Duration, what: &str, done: impl Fn(&str) -> bool) {
        let until = Instant::now() + within;
        loop {
            let screen = self.screen();
            if done(&screen) {
                return;
            }
            assert!(
                Instant::now() < until,
                "waited {within:?} for {what}; screen:\n{screen}"
            );
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = self.tmux(&["kill-server"]);
    }
}

/// Pids of running processes whose command line has every one of `words`.
fn pids_with(words: &[&str]) -> Vec<u32> {
    let Ok(entries) = std::fs::read_dir("/proc") else {
        return Vec::new();
    };
    entries
        .filter_map(|e| e.ok())
        .filter_map(|e| e.file_name().to_str()?.parse::<u32>().ok())
        .filter(|pid| {
            let cmdline = std::fs::read(format!("/proc/{pid}/cmdline")).unwrap_or_default();
            let args: Vec<String> = cmdline
                .split(|b| *b == 0)
                .map(|a| String::from_utf8_lossy(a).into_owned())
                .collect();
            words.iter().all(|w| args.iter().any(|a| a == w))
        })
        .collect()
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn killing_the_console_with_sigkill_mid_jog_stops_the_arm() {
    let sim = simulator().await;
    let addr = modbus_addr(&sim);
    let dir = log_dir();
    let command = format!(
        "exec env ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} {BIN} --modbus {addr} --unit 1 --key-release repeat",
        d = dir.display(),
    );
    let tmux = Tmux::start(&command);
    tmux.wait_for(Duration::from_secs(20), "the link and the guard", |s| {
        s.contains("LINK UP") && s.contains("GUARD OK")
    })
    .await;
    let console_pid = tmux.pane_pid();
    let guards = pids_with(&["guard", "--modbus", &addr]);
    assert_eq!(guards.len(), 1, "one guard process runs: {guards:?}");

    // 10 % of 250 mm/s: seconds away from any limit.
    for speed in ["40%", "30%", "20%", "10%"] {
        tmux.key("-");
        let shown = format!("speed {speed}");
        tmux.wait_for(Duration::from_secs(5), &shown, |s| s.contains(&shown))
            .await;
    }

    // Hold w (tmux has no releases: a press, then a repeat every 30 ms), and kill the console
    // with SIGKILL while the arm moves: no code of the console runs after that.
    let holding = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    let keys = {
        let holding = holding.clone();
        let socket = tmux.socket.clone();
        std::thread::spawn(move || {
            while holding.load(std::sync::atomic::Ordering::Relaxed) {
                let _ = std::process::Command::new("tmux")
                    .args(["-L", &socket, "send-keys", "-t", "console", "w"])
                    .output();
                std::thread::sleep(Duration::from_millis(30));
            }
        })
    };
    let moving = wait_moving(&sim, true, Duration::from_secs(10)).await;
    tokio::time::sleep(Duration::from_millis(300)).await;
    let (still_moving, x_at_kill) = arm_state(&sim).await;
    let killed = std::process::Command::new("kill")
        .args(["-9", &console_pid.to_string()])
        .status()
        .expect("kill");
    // `kill` has returned: the signal is delivered.
    let killed_at = Instant::now();
    holding.store(false, std::sync::atomic::Ordering::Relaxed);
    assert!(
        moving.is_some() && still_moving,
        "w jogged the arm over Modbus"
    );
    assert!(killed.success(), "kill -9 {console_pid}");

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
    let until = Instant::now() + Duration::from_secs(5);
    while guards
        .iter()
        .any(|pid| std::path::Path::new(&format!("/proc/{pid}")).exists())
        && Instant::now() < until
    {
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
    let left: Vec<u32> = guards
        .iter()
        .copied()
        .filter(|pid| std::path::Path::new(&format!("/proc/{pid}")).exists())
        .collect();
    for pid in &left {
        let _ = std::process::Command::new("kill")
            .arg(pid.to_string())
            .status();
    }
    assert!(left.is_empty(), "the guard exited after the stop: {left:?}");
}

/// The status bar's two lines as text, 80 columns wide.
fn status_text(app: &armjog::console::app::App) -> (String, ratatui::buffer::Buffer) {
    use armjog::console::ui::{Theme, status};
    let mut terminal =
        ratatui::Terminal::new(ratatui::backend::TestBackend::new(80, 2)).expect("terminal");
    terminal
        .draw(|f| status::draw(f, f.area(), app, &Theme { color: true }))
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
    use armjog::link::arm::LinkStatus;

    let t0 = std::time::Instant::now();
    let mut app = App::new(
        AppConfig {
            keymap: Keymap::builtin("default").expect("keymap"),
            release_mode: ReleaseMode::Reported,
            refresh: Duration::from_millis(100),
            positions_on_operator: false,
            max_jog_speed: 0.25,
            frames: true,
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
    assert!(app.jog.active().is_none(), "nothing held any more");
    let (message, severity, _) = app.message.clone().expect("a message");
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
