//! Pastes into the real console in tmux: a bracketed paste is text, never keys, and a paste
//! where bracketed paste is off cannot answer the question its keys open.

use std::time::Duration;

use crate::tmux::session::{Tmux, tcp_x};

const HOME_QUESTION: &str = "Move the arm to its home pose?";

#[test]
fn pasting_why_never_sends_the_arm_home() {
    let dir = std::env::temp_dir().join(format!("armjog-tmux-paste-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let command = format!(
        "ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} {bin}; echo ARMJOG-EXITED-$?; sleep 30",
        d = dir.display(),
        bin = env!("CARGO_BIN_EXE_armjog"),
    );
    let tmux = Tmux::start(&command, 100, 30);
    let screen = tmux.wait_for(Duration::from_secs(15), "the link to come up", |s| {
        s.contains("LINK UP") && s.contains("pos mm") && s.contains("Command log")
    });
    let x0 = tcp_x(&screen).expect("tcp x on screen");

    // The console asked for bracketed paste, so tmux sends the markers: one message, no keys.
    tmux.paste("why", true);
    let said = tmux.wait_for(Duration::from_secs(5), "the paste to be ignored", |s| {
        s.contains("paste ignored")
    });
    assert!(!said.contains(HOME_QUESTION), "no question:\n{said}");
    std::thread::sleep(Duration::from_millis(500));
    let x1 = tmux.settled_x(Duration::from_secs(10));
    assert!(
        (x1 - x0).abs() < 0.5,
        "a bracketed paste moved: {x0} -> {x1}"
    );

    // The same text as bare keys (a terminal without bracketed paste): h asks, and the y
    // that follows it within a millisecond does not answer. (The w is a tap: a 5 mm step.)
    tmux.paste("why", false);
    let asked = tmux.wait_for(Duration::from_secs(5), "the home question", |s| {
        s.contains(HOME_QUESTION)
    });
    std::thread::sleep(Duration::from_millis(1500));
    let still = tmux.screen();
    assert!(
        still.contains(HOME_QUESTION),
        "still asking:\n{still}\n{asked}"
    );
    let x2 = tmux.settled_x(Duration::from_secs(10));
    assert!(
        x2 - x1 < 5.5 && x2 >= x1 - 0.5,
        "only the tap's step, never home (80 mm away): {x1} -> {x2}"
    );
    tmux.keys(&["Escape"]);
    tmux.wait_for(Duration::from_secs(5), "the question to close", |s| {
        !s.contains(HOME_QUESTION)
    });

    tmux.keys(&["q"]);
    let back = tmux.wait_for(Duration::from_secs(5), "the console to exit", |s| {
        s.contains("ARMJOG-EXITED-")
    });
    assert!(back.contains("ARMJOG-EXITED-0"), "exit status 0:\n{back}");
}
