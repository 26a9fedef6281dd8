//! The console as a technician sees it: the real binary in tmux, on the built-in simulated
//! arm. tmux reports no key releases, so this exercises the auto-repeat fallback. `.ci/run`
//! installs tmux.

use std::io::Write;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// One tmux server of our own, killed on drop.
pub(crate) struct Tmux {
    socket: String,
    session: String,
    /// A control-mode client of the session, which auto-repeats are typed through: a
    /// `tmux send-keys` process per repeat lets a loaded machine scatter the repeats until the
    /// console no longer sees a hold.
    control: Mutex<Option<(Child, ChildStdin)>>,
}

impl Tmux {
    pub(crate) fn start(command: &str, width: u16, height: u16) -> Tmux {
        // One server per test: tests of this binary run at once.
        static SERVERS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let server = SERVERS.fetch_add(1, Ordering::Relaxed);
        let socket = format!("armjog-test-{}-{server}", std::process::id());
        let session = "console".to_string();
        let status = Command::new("tmux")
            .args(["-L", &socket, "new-session", "-d", "-s", &session])
            .args(["-x", &width.to_string(), "-y", &height.to_string()])
            .arg(command)
            .status()
            .expect("tmux must be installed (apt-get install -y tmux)");
        assert!(status.success(), "tmux new-session failed");
        Tmux {
            socket,
            session,
            control: Mutex::new(None),
        }
    }

    /// Types `key` through the control-mode client (started on first use): no process per key.
    fn repeat_key(&self, key: &str) {
        let mut control = self.control.lock().expect("control client lock");
        if control.is_none() {
            let mut child = Command::new("tmux")
                .args([
                    "-L",
                    &self.socket,
                    "-C",
                    "attach-session",
                    "-t",
                    &self.session,
                ])
                .stdin(Stdio::piped())
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("tmux control client");
            let stdin = child.stdin.take().expect("control client stdin");
            *control = Some((child, stdin));
        }
        let (_, stdin) = control.as_mut().expect("control client started");
        writeln!(stdin, "send-keys -t {} {key}", self.session)
            .and_then(|()| stdin.flush())
            .expect("tmux control client takes keys");
    }

    pub(crate) fn keys(&self, keys: &[&str]) {
        let status = Command::new("tmux")
            .args(["-L", &self.socket, "send-keys", "-t", &self.session])
            .args(keys)
            .status()
            .expect("tmux send-keys");
        assert!(status.success());
    }

    /// Pastes `text` as a terminal does: with `bracketed`, inside the bracketed-paste markers
    /// (tmux adds them only for a pane that asked for them); without, as bare keys.
    pub(crate) fn paste(&self, text: &str, bracketed: bool) {
        let set = Command::new("tmux")
            .args(["-L", &self.socket, "set-buffer", "-b", "armjog", text])
            .status()
            .expect("tmux set-buffer");
        assert!(set.success());
        let mut paste = Command::new("tmux");
        paste.args(["-L", &self.socket, "paste-buffer", "-d", "-b", "armjog"]);
        paste.args(["-t", &self.session]);
        if bracketed {
            paste.arg("-p");
        }
        assert!(paste.status().expect("tmux paste-buffer").success());
    }

    /// Resizes the window, as a technician dragging the terminal smaller or larger.
    fn resize(&self, width: u16, height: u16) {
        let status = Command::new("tmux")
            .args(["-L", &self.socket, "resize-window", "-t", &self.session])
            .args(["-x", &width.to_string(), "-y", &height.to_string()])
            .status()
            .expect("tmux resize-window");
        assert!(status.success(), "tmux resize-window failed");
    }

    /// The auto-repeat of a held key: `key` every `interval` for `span`.
    fn repeat(&self, key: &str, interval: Duration, span: Duration) {
        self.repeat_watching(key, interval, span, "");
    }

    /// [`Tmux::repeat`], looking at the screen while the repeats go on (not after them: the
    /// console stops a few intervals after the last one); whether `shown` was ever on it. The
    /// screen is watched from another thread, so that capturing it never delays a repeat.
    fn repeat_watching(&self, key: &str, interval: Duration, span: Duration, shown: &str) -> bool {
        let until = Instant::now() + span;
        let repeating = AtomicBool::new(true);
        std::thread::scope(|scope| {
            let watcher = scope.spawn(|| {
                while !shown.is_empty() && repeating.load(Ordering::Relaxed) {
                    if self.screen().contains(shown) {
                        return true;
                    }
                    std::thread::sleep(Duration::from_millis(50));
                }
                false
            });
            while Instant::now() < until {
                let sent = Instant::now();
                self.repeat_key(key);
                // No catching up after a stall: a burst of back-to-back repeats is no keyboard's.
                std::thread::sleep(interval.saturating_sub(sent.elapsed()));
            }
            repeating.store(false, Ordering::Relaxed);
            watcher.join().expect("screen watcher")
        })
    }

    /// Waits until the TCP x stops changing (two equal readings 400 ms apart) and returns it.
    pub(crate) fn settled_x(&self, within: Duration) -> f64 {
        let until = Instant::now() + within;
        let mut last = None;
        loop {
            let x = tcp_x(&self.screen());
            if x.is_some() && x == last {
                return x.unwrap_or_default();
            }
            assert!(
                Instant::now() < until,
                "tcp x did not settle within {within:?}; screen:\n{}",
                self.screen()
            );
            last = x;
            std::thread::sleep(Duration::from_millis(400));
        }
    }

    pub(crate) fn screen(&self) -> String {
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
    pub(crate) fn wait_for(
        &self,
        within: Duration,
        what: &str,
        done: impl Fn(&str) -> bool,
    ) -> String {
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
        if let Ok(mut control) = self.control.lock()
            && let Some((mut child, stdin)) = control.take()
        {
            // End of input detaches the control client.
            drop(stdin);
            let _ = child.wait();
        }
        let _ = Command::new("tmux")
            .args(["-L", &self.socket, "kill-server"])
            .status();
    }
}

/// The TCP x in mm from the tool panel's "pos mm" row.
pub(crate) fn tcp_x(screen: &str) -> Option<f64> {
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
        // The whole first frame, not one caught mid-draw.
        s.contains("LINK UP") && s.contains("pos mm") && s.contains("Command log")
    });
    for panel in ["Joints", "Tool (TCP", "Arm", "Positions", "Command log"] {
        assert!(screen.contains(panel), "panel {panel} missing:\n{screen}");
    }
    assert!(
        screen.contains("keys: auto-repeat fallback"),
        "mode shown:\n{screen}"
    );
    let x0 = tcp_x(&screen).expect("tcp x on screen");

    // A tap of w is one small step (5 mm at most), never a jog.
    tmux.keys(&["w"]);
    std::thread::sleep(Duration::from_millis(1500));
    let x_tap = tmux.settled_x(Duration::from_secs(10));
    assert!(
        x_tap > x0 + 0.5 && x_tap <= x0 + 5.5,
        "a tap steps at most 5 mm: {x0} -> {x_tap}"
    );

    // Hold w: a press, then auto-repeat every 30 ms after a 500 ms onset.
    tmux.keys(&["w"]);
    std::thread::sleep(Duration::from_millis(500));
    let repeat = Duration::from_millis(30);
    let jogging = tmux.repeat_watching("w", repeat, Duration::from_millis(800), "JOG +X");
    assert!(jogging, "jogging shown while held");
    // The repeats stopped: the console stops the arm by itself.
    let stopped = tmux.wait_for(Duration::from_secs(5), "the jog to stop", |s| {
        s.contains(" idle ")
    });
    let x1 = tcp_x(&stopped).expect("tcp x");
    assert!(x1 > x_tap + 20.0, "w held moved +X: {x_tap} -> {x1}");
    std::thread::sleep(Duration::from_millis(300));
    let still = tcp_x(&tmux.screen()).expect("tcp x");
    assert!(
        (still - x1).abs() < 0.5,
        "no motion after the stop: {x1} -> {still}"
    );

    // A burst of w at about 30 Hz for 1.5 s, with no onset pause: a hold too.
    let jogging = tmux.repeat_watching("w", repeat, Duration::from_millis(1500), "JOG +X");
    assert!(jogging, "jogging shown during the burst");
    tmux.wait_for(Duration::from_secs(5), "the burst's jog to stop", |s| {
        s.contains(" idle ")
    });
    let x2 = tmux.settled_x(Duration::from_secs(10));
    assert!(x2 > x1 + 20.0, "a 1.5 s burst jogged: {x1} -> {x2}");

    // Nothing starts by itself: w held (repeating) while the window is made too small and
    // large again stops and stays stopped until its repeats pause.
    tmux.keys(&["w"]);
    std::thread::sleep(Duration::from_millis(500));
    let jogging = tmux.repeat_watching("w", repeat, Duration::from_millis(600), "JOG +X");
    assert!(jogging, "held w jogs again");
    tmux.resize(30, 8);
    tmux.repeat("w", repeat, Duration::from_millis(300));
    tmux.resize(100, 30);
    tmux.repeat("w", repeat, Duration::from_millis(300));
    let x_resumed = tcp_x(&tmux.screen()).expect("tcp x after the resize");
    tmux.repeat("w", repeat, Duration::from_millis(500));
    let held_on = tmux.screen();
    let x_held = tcp_x(&held_on).expect("tcp x");
    assert!(
        held_on.contains(" idle ") && (x_held - x_resumed).abs() < 0.5,
        "no motion while w keeps repeating after the resize: {x_resumed} -> {x_held}\n{held_on}"
    );
    let x3 = tmux.settled_x(Duration::from_secs(10));
    assert!(
        (x3 - x_held).abs() < 0.5,
        "nothing moved after the repeats paused: {x_held} -> {x3}"
    );

    // Help lists the active keymap; any key closes it.
    tmux.keys(&["?"]);
    let help = tmux.wait_for(Duration::from_secs(2), "help", |s| {
        s.contains("Help: keymap")
    });
    assert!(help.contains("jog_x_plus"), "{help}");
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
