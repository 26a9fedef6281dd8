//! `armjog --arm NAME` end to end: the real console in tmux opens on the arm its profile names
//! (the simulator, reached over loopback as a real arm is), with the profile's cap, and keys its
//! book and its audit by the profile's name.

use std::time::Duration;

use armjog::sim::{SimConfig, Simulator};

use crate::tmux::session::Tmux;

#[test]
fn the_console_opens_on_the_arm_its_profile_names() {
    let runtime = tokio::runtime::Runtime::new().expect("runtime");
    let sim = runtime
        .block_on(Simulator::start(SimConfig::ephemeral()))
        .expect("sim");
    let modbus = sim.modbus_addr.expect("modbus");
    let dir = std::env::temp_dir().join(format!("armjog-profile-e2e-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let config = dir.join("config.toml");
    std::fs::write(
        &config,
        format!(
            "[arms.bench]\ntalos = \"{}\"\nmodbus = \"{modbus}\"\nmax_jog_speed = 100\n",
            sim.talos_addr
        ),
    )
    .expect("write config");
    let command = format!(
        "ARMJOG_CONFIG={c} ARMJOG_DATA_DIR={d} ARMJOG_LOG_DIR={d} ARMJOG_STATE_DIR={d} \
         {bin} --arm bench --key-release repeat; echo ARMJOG-EXITED-$?; sleep 30",
        c = config.display(),
        d = dir.display(),
        bin = env!("CARGO_BIN_EXE_armjog"),
    );
    let tmux = Tmux::start(&command, 120, 32);

    // The link is the profile's: both of the simulator's addresses, and its cap (the speed
    // keys' 50 % is 50 mm/s of 100, not 125 of the default 250).
    let talos = format!("talos {}", sim.talos_addr);
    let modbus_link = format!("modbus {modbus}");
    let screen = tmux.wait_for(Duration::from_secs(15), "the link to come up", |s| {
        s.contains("LINK UP") && s.contains("pos mm") && s.contains("Command log")
    });
    assert!(screen.contains(&talos), "{talos} on screen:\n{screen}");
    assert!(
        screen.contains(&modbus_link),
        "{modbus_link} on screen:\n{screen}"
    );
    assert!(
        screen.contains("(≤50 mm/s)"),
        "the profile's cap:\n{screen}"
    );

    // A saved position goes to the book named for the profile.
    tmux.keys(&["p"]);
    tmux.wait_for(Duration::from_secs(5), "the save form", |s| {
        s.contains("Save current pose")
    });
    tmux.keys(&["pick", "Enter"]);
    let book = dir.join("positions").join("arm-bench.json");
    let until = std::time::Instant::now() + Duration::from_secs(10);
    while !book.exists() {
        assert!(
            std::time::Instant::now() < until,
            "no {}; screen:\n{}",
            book.display(),
            tmux.screen()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let saved = std::fs::read_to_string(&book).expect("read the book");
    assert!(saved.contains("\"pick\""), "{saved}");

    tmux.keys(&["q"]);
    let back = tmux.wait_for(Duration::from_secs(10), "the console to exit", |s| {
        s.contains("ARMJOG-EXITED-")
    });
    assert!(back.contains("ARMJOG-EXITED-0"), "exit status 0:\n{back}");

    // The audit names the session by the profile, and says where the arm was reached.
    let audit = std::fs::read_dir(&dir)
        .expect("list the dir")
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("audit-"))
        })
        .expect("an audit file");
    let text = std::fs::read_to_string(&audit).expect("read the audit");
    let start = text.lines().next().expect("a first entry");
    let entry: serde_json::Value = serde_json::from_str(start).expect("JSON");
    assert_eq!(entry["event"], "session_start");
    assert_eq!(entry["arm"], "bench");
    assert_eq!(entry["target"], format!("talos-{}", sim.talos_addr));
    drop(sim);
}
