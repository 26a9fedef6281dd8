//! Arm profiles through the built binary: `status` and `modbus` reach the simulator by `--arm`,
//! a bad profile is refused before anything connects, `armjog arms` lists the profiles.

use std::path::Path;

use armjog::sim::{SimConfig, Simulator};

use crate::armjog_run::{self, Run, run};
use crate::profiles::{GOOD, armjog, config_file};

/// `armjog args...` with the default config file in `config_home` (`$XDG_CONFIG_HOME`).
async fn default_config_armjog(config_home: &Path, args: &[&str]) -> Run {
    let mut command = armjog_run::command(args);
    command
        .env_remove("ARMJOG_CONFIG")
        .env_remove("ARMJOG_ARM")
        .env("XDG_CONFIG_HOME", config_home);
    run(command).await
}

/// A profile `sim1` on the simulator, with a Home action id it does not have.
fn sim_profile(sim: &Simulator) -> String {
    let modbus = sim.modbus_addr.expect("modbus");
    format!(
        "[arms.sim1]\ntalos = \"{}\"\nmodbus = \"{modbus}\"\nhome_action_id = 9\n",
        sim.talos_addr
    )
}

#[tokio::test(flavor = "multi_thread")]
async fn status_and_modbus_reach_the_simulator_by_its_profile() {
    let sim = Simulator::start(SimConfig::ephemeral()).await.expect("sim");
    let (_dir, config) = config_file(&sim_profile(&sim));

    let status = armjog(&config, &[], &["status", "--arm", "sim1", "--json"]).await;
    assert_eq!(status.code, 0, "{}", status.stderr);
    let json: serde_json::Value = serde_json::from_str(status.stdout.trim()).expect("JSON");
    assert!(json["robot_state"].is_string(), "{json}");

    // ARMJOG_ARM names it as --arm does.
    let status = armjog(&config, &[("ARMJOG_ARM", "sim1")], &["status"]).await;
    assert_eq!(status.code, 0, "{}", status.stderr);
    assert!(status.stdout.contains("robot state"), "{}", status.stdout);

    // The profile's Home action id reaches the arm: the simulator has no action 9.
    let home = armjog(&config, &[], &["modbus", "--arm", "sim1", "home"]).await;
    assert_eq!(home.code, 1, "{} / {}", home.stdout, home.stderr);
    assert!(home.stderr.contains("action 9"), "{}", home.stderr);
    // And a flag wins over it: the simulator's Home is 2.
    let home = armjog(
        &config,
        &[],
        &["--arm", "sim1", "modbus", "home", "--action-id", "2"],
    )
    .await;
    assert_eq!(home.code, 0, "{} / {}", home.stdout, home.stderr);
    assert!(home.stdout.contains("home: completed"), "{}", home.stdout);

    let send = armjog(
        &config,
        &[],
        &["send", "get-speed", "--arm", "sim1", "--json"],
    )
    .await;
    assert_eq!(send.code, 0, "{}", send.stderr);
    assert!(send.stdout.contains("get_speed"), "{}", send.stdout);
}

#[tokio::test(flavor = "multi_thread")]
async fn a_bad_profile_is_refused_before_anything_connects() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("addr");
    let (_dir, config) = config_file(&format!("[arms.cell3]\nmodbus = \"{addr}\"\nunti = 1\n"));
    let run = armjog(&config, &[], &["status", "--arm", "cell3"]).await;
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(
        run.stderr.trim(),
        format!(
            "armjog: {}:3: unknown key 'unti'; did you mean 'unit'?",
            config.display()
        )
    );
    let unknown = armjog(&config, &[], &["--arm", "cell4"]).await;
    assert_eq!(unknown.code, 2, "{}", unknown.stderr);
    // No connection was made.
    let accepted =
        tokio::time::timeout(std::time::Duration::from_millis(200), listener.accept()).await;
    assert!(accepted.is_err(), "something connected");

    let missing = config.with_file_name("missing.toml");
    let run = armjog(&missing, &[], &["--arm", "cell3"]).await;
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains("missing.toml: no such file"),
        "{}",
        run.stderr
    );
}

#[tokio::test(flavor = "multi_thread")]
async fn arms_lists_the_profiles_with_their_targets() {
    let (_dir, config) = config_file(GOOD);
    let run = armjog(&config, &[], &["arms"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "cell3  talos 192.168.1.20  modbus 192.168.1.10 unit 1\n\
         bench  modbus 10.0.0.5:1502\n"
    );
    // --config before the command word, and a file with no arm in it.
    let (_dir, empty) = config_file("[arms.sim]\n");
    let run = armjog(
        &config,
        &[],
        &["--config", &empty.display().to_string(), "arms"],
    )
    .await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(run.stdout, "sim  the built-in simulated arm\n");

    // A file named (ARMJOG_CONFIG, --config) that is not there is refused, naming it.
    let missing = config.with_file_name("missing.toml");
    let run = armjog(&missing, &[], &["arms"]).await;
    assert_eq!(run.code, 2, "{}{}", run.stdout, run.stderr);
    assert_eq!(
        run.stderr,
        format!(
            "armjog: {}: no such file (arm profiles go there)\n",
            missing.display()
        )
    );
    let run = armjog(
        &config,
        &[],
        &["arms", "--config", "/nonexistent/armjog/config.toml"],
    )
    .await;
    assert_eq!(run.code, 2, "{}{}", run.stdout, run.stderr);
    assert!(
        run.stderr
            .contains("/nonexistent/armjog/config.toml: no such file"),
        "{}",
        run.stderr
    );
    // The default file not there: no profiles yet, which is fine.
    let home = tempfile::tempdir().expect("temp dir");
    let default = home.path().join("armjog").join("config.toml");
    let run = default_config_armjog(home.path(), &["arms"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout.starts_with(&format!(
            "no arm profiles: {} does not exist",
            default.display()
        )),
        "{}",
        run.stdout
    );

    let (_dir, bad) = config_file("[arms.cell3]\ntalso = \"x\"\n");
    let run = armjog(&bad, &[], &["arms"]).await;
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.contains("config.toml:2: unknown key 'talso'"),
        "{}",
        run.stderr
    );
}
