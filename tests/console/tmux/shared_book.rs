//! Two real consoles on one `--positions` file, end to end: each saves a position on one
//! simulated arm (over Modbus the book is where positions live); the file keeps both, and the
//! console that saved second shows the first one's position and says it came in.

use std::path::Path;
use std::time::{Duration, Instant};

use armjog::sim::{SimConfig, Simulator};

use crate::tmux::session::Tmux;

fn wait_for_file(path: &Path, within: Duration, what: &str, done: impl Fn(&str) -> bool) {
    let until = Instant::now() + within;
    loop {
        let text = std::fs::read_to_string(path).unwrap_or_default();
        if done(&text) {
            return;
        }
        assert!(
            Instant::now() < until,
            "{what}: not within {within:?}:\n{text}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn save_pose(tmux: &Tmux, name: &str) {
    tmux.keys(&["p"]);
    tmux.wait_for(Duration::from_secs(5), "the save form", |s| {
        s.contains("Save current pose")
    });
    tmux.keys(&[name, "Enter"]);
}

#[test]
fn two_consoles_saving_to_one_book_keep_both_positions() {
    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    let sim = runtime
        .block_on(Simulator::start(SimConfig::ephemeral()))
        .expect("sim");
    let modbus = sim.modbus_addr.expect("modbus");
    let dir = tempfile::tempdir().expect("temp dir");
    let book = dir.path().join("book.json");
    let console = |n: u32| {
        let own = dir.path().join(format!("console{n}"));
        std::fs::create_dir_all(&own).expect("console dir");
        let command = format!(
            "ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} ARMJOG_STATE_DIR={d} {bin} --modbus {modbus} \
             --positions {book} --key-release repeat; echo ARMJOG-EXITED-$?; sleep 30",
            d = own.display(),
            bin = env!("CARGO_BIN_EXE_armjog"),
            book = book.display(),
        );
        Tmux::start(&command, 120, 32)
    };
    let one = console(1);
    let two = console(2);
    for tmux in [&one, &two] {
        tmux.wait_for(Duration::from_secs(15), "the link to come up", |s| {
            s.contains("LINK UP") && s.contains("pos mm") && s.contains("Positions")
        });
    }

    // Both consoles have read the (empty) book. Console 1 saves X1, then console 2 X3.
    save_pose(&one, "x1");
    wait_for_file(&book, Duration::from_secs(10), "x1 written", |t| {
        t.contains("\"x1\"")
    });
    save_pose(&two, "x3");
    wait_for_file(&book, Duration::from_secs(10), "x3 written", |t| {
        t.contains("\"x3\"")
    });
    let text = std::fs::read_to_string(&book).expect("the book");
    assert!(
        text.contains("\"x1\""),
        "console 1's position kept:\n{text}"
    );
    let screen = two.wait_for(Duration::from_secs(5), "x1 shown on console 2", |s| {
        s.contains("x1") && s.contains("x3")
    });
    assert!(
        screen.contains("changed by another program"),
        "console 2 says so:\n{screen}"
    );

    for tmux in [&one, &two] {
        tmux.keys(&["q"]);
        let back = tmux.wait_for(Duration::from_secs(10), "the console to exit", |s| {
            s.contains("ARMJOG-EXITED-")
        });
        assert!(back.contains("ARMJOG-EXITED-0"), "exit status 0:\n{back}");
    }
    let text = std::fs::read_to_string(&book).expect("the book");
    assert!(text.contains("\"x1\"") && text.contains("\"x3\""), "{text}");
    drop(sim);
}
