//! A profile's values are checked as config.toml is read, each by its option's own parser
//! (`cli::values`), and named by the file, line and key, by every command that reads the file.

use crate::profiles::{armjog, config_file, error, parse};

/// Every value is checked as the file is read, by the option's own parser, and named by its
/// key: never as an option nobody typed (`--max-jog-speed -5 mm/s`) once the console starts.
#[test]
fn every_value_is_checked_at_load_and_named_by_its_key() {
    let speed = "must be above 0 and at most 500 mm/s (the arm's twist limit)";
    for (line, says) in [
        ("max_jog_speed = -5", format!("max_jog_speed = -5: {speed}")),
        ("max_jog_speed = 0", format!("max_jog_speed = 0: {speed}")),
        (
            "max_jog_speed = 0.0",
            format!("max_jog_speed = 0.0: {speed}"),
        ),
        (
            "max_jog_speed = nan",
            format!("max_jog_speed = nan: {speed}"),
        ),
        (
            "max_jog_speed = inf",
            format!("max_jog_speed = inf: {speed}"),
        ),
        (
            "max_jog_speed = -inf",
            format!("max_jog_speed = -inf: {speed}"),
        ),
        (
            "max_jog_speed = 600",
            format!("max_jog_speed = 600: {speed}"),
        ),
        (
            "operator_full_speed = 500.5",
            format!("operator_full_speed = 500.5: {speed}"),
        ),
        (
            "refresh_hz = 1",
            "refresh_hz = 1: must be 2.5 to 100 (re-sending well inside the 500 ms watchdog)"
                .to_string(),
        ),
        (
            "telemetry_hz = 0",
            "telemetry_hz = 0: must be 1 to 200".to_string(),
        ),
        (
            "home_action_id = 0",
            "home_action_id = 0: 0 is outside 1 to 65535".to_string(),
        ),
    ] {
        let text = format!("[arms.cell3]\ntalos = \"op\"\n{line}\n");
        assert_eq!(error(&text), format!("config.toml:3: {says}"), "{line}");
    }
    // The edges are values.
    for line in [
        "max_jog_speed = 500",
        "max_jog_speed = 0.5",
        "refresh_hz = 2.5",
        "telemetry_hz = 200",
        "home_action_id = 65535",
    ] {
        let text = format!("[arms.cell3]\n{line}\n");
        assert!(parse(&text).is_ok(), "{line}");
    }
}

/// The case: `max_jog_speed = -5` passed `armjog arms` and `status --arm`, and the
/// console then named `--max-jog-speed`. Now every reader refuses the file, naming its line and
/// key, before anything connects.
#[tokio::test(flavor = "multi_thread")]
async fn a_bad_value_is_refused_by_every_reader_at_load() {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("addr");
    for value in ["-5", "0", "nan", "inf", "600"] {
        let (_dir, config) = config_file(&format!(
            "[arms.cell3]\nmodbus = \"{addr}\"\nmax_jog_speed = {value}\n"
        ));
        let expected = format!(
            "armjog: {}:3: max_jog_speed = {value}: must be above 0 and at most 500 mm/s (the \
             arm's twist limit)\n",
            config.display()
        );
        for args in [
            &["arms"][..],
            &["status", "--arm", "cell3"],
            &["modbus", "--arm", "cell3", "stop"],
            &["--arm", "cell3"],
        ] {
            let run = armjog(&config, &[], args).await;
            assert_eq!(
                run.code, 2,
                "{args:?} {value}: {}{}",
                run.stdout, run.stderr
            );
            assert_eq!(run.stderr, expected, "{args:?}");
        }
    }
    let accepted =
        tokio::time::timeout(std::time::Duration::from_millis(200), listener.accept()).await;
    assert!(accepted.is_err(), "something connected");
}
