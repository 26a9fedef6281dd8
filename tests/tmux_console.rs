//! The console as a technician sees it: the real binary in tmux, on the built-in simulated
//! arm. tmux reports no key releases, so this exercises the auto-repeat fallback. `.ci/run`
//! installs tmux.

use std::process::Command;
use std::time::{Duration, Instant};

/// One tmux server of our own, killed on drop.
struct Tmux {
    socket: String,
    session: String,
}

impl Tmux {
    fn start(command: &str, width: u16, height: u16) -> Tmux {
        let socket = format!("armjog-test-{}", std::process::id());
        let session = "console".to_string();
        let status = Command::new("tmux")
            .args(["-L", &socket, "new-session", "-d", "-s", &session])
            .args(["-x", &width.to_string(), "-y", &height.to_string()])
            .arg(command)
            .status()
            .expect("tmux must be installed (apt-get install -y tmux)");
        assert!(status.success(), "tmux new-session failed");
        Tmux { socket, session }
    }

    fn keys(&self, keys: &[&str]) {
        let status = Command::new("tmux")
            .args(["-L", &self.socket, "send-keys", "-t", &self.session])
            .args(keys)
            .status()
            .expect("tmux send-keys");
        assert!(status.success());
    }

    fn screen(&self) -> String {
        let out = Command::new("tmux")
            .args([
                "-L",
                &self.socket,
                "capture-pane",
                "-p",
                "-t",
                &self.session,
            ])
            .output()
            .expect("tmux capture-pane");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Waits until the screen satisfies `done`; panics with the screen after `within`.
    fn wait_for(&self, within: Duration, what: &str, done: impl Fn(&str) -> bool) -> String {
        let until = Instant::now() + within;
        loop {
            let screen = self.screen();
            if done(&screen) {
                return screen;
            }
            assert!(
                Instant::now() < until,
                "waited {within:?} for {what}; screen:\n{screen}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["-L", &self.socket, "kill-server"])
            .status();
    }
}

/// The TCP x in mm from the tool panel's "pos mm" row.
fn tcp_x(screen: &str) -> Option<f64> {
    let line = screen.lines().find(|l| l.contains("pos mm"))?;
    let after = line.split("pos mm").nth(1)?;
    after.split_whitespace().next()?.parse().ok()
}

#[test]
fn the_console_opens_on_the_simulator_jogs_shows_help_and_gives_the_terminal_back() {
    let dir = std::env::temp_dir().join(format!("armjog-tmux-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let command = format!(
        "ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} {bin}; echo ARMJOG-EXITED-$?; sleep 30",
        d = dir.display(),
        bin = env!("CARGO_BIN_EXE_armjog"),
    );
    let tmux = Tmux::start(&command, 100, 30);

    // The panels, the link to the built-in arm and the key-release mode.
    let screen = tmux.wait_for(Duration::from_secs(15), "the link to come up", |s| {
        s.contains("LINK UP") && s.contains("pos mm")
    });
    for panel in ["Joints", "Tool (TCP", "Arm", "Positions", "Command log"] {
        assert!(screen.contains(panel), "panel {panel} missing:\n{screen}");
    }
    assert!(
        screen.contains("keys: auto-repeat fallback"),
        "mode shown:\n{screen}"
    );
    let x0 = tcp_x(&screen).expect("tcp x on screen");

    // Hold w: a press, then auto-repeat every 30 ms after a 500 ms onset.
    tmux.keys(&["w"]);
    std::thread::sleep(Duration::from_millis(500));
    for _ in 0..15 {
        tmux.keys(&["w"]);
        std::thread::sleep(Duration::from_millis(30));
    }
    let jogging = tmux.screen();
    assert!(jogging.contains("JOG +X"), "jogging shown:\n{jogging}");
    // The repeats stopped: the console stops the arm by itself.
    let stopped = tmux.wait_for(Duration::from_secs(2), "the jog to stop", |s| {
        s.contains(" idle ")
    });
    let x1 = tcp_x(&stopped).expect("tcp x");
    assert!(x1 > x0 + 20.0, "w moved +X: {x0} -> {x1}");
    std::thread::sleep(Duration::from_millis(300));
    let still = tcp_x(&tmux.screen()).expect("tcp x");
    assert!(
        (still - x1).abs() < 0.5,
        "no motion after the stop: {x1} -> {still}"
    );

    // Help lists the active keymap; any key closes it.
    tmux.keys(&["?"]);
    let help = tmux.wait_for(Duration::from_secs(2), "help", |s| {
        s.contains("Help: keymap")
    });
    assert!(help.contains("jog +X (hold)"), "{help}");
    tmux.keys(&["Escape"]);
    tmux.wait_for(Duration::from_secs(2), "help to close", |s| {
        !s.contains("Help: keymap")
    });

    // Quit: the terminal comes back (the shell's line is on the normal screen).
    tmux.keys(&["q"]);
    let back = tmux.wait_for(Duration::from_secs(5), "the console to exit", |s| {
        s.contains("ARMJOG-EXITED-")
    });
    assert!(back.contains("ARMJOG-EXITED-0"), "exit status 0:\n{back}");
    assert!(
        !back.contains("Joints"),
        "the alternate screen is gone:\n{back}"
    );
}
