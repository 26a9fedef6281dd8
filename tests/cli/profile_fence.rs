//! A profile's fence table (`[arms.NAME.fence]`): read whole with the rest of the profile, every
//! mistake named by file, line and key (exit 2) before anything connects; `armjog arms` shows it,
//! and `--arm` hands it on. What each value means is `link::fence`'s (its own tests).

use std::ffi::OsString;

use armjog::cli::profiles::{self, Parsed};
use armjog::link::fence::{Aabb, KeepOut};

use crate::profiles::{armjog, config_file, error, parse};

/// The issue's example, on the built-in simulated arm (no talos, no modbus), line by line.
const FENCED: &str = r#"# cell 3, fenced
[arms.cell3]
keymap = "numpad"

[arms.cell3.fence]
inside = { min = [-600, -600, 0], max = [800, 600, 900] }  # the box the tool stays in: mm, base frame
tool_radius = 40          # mm: the sphere around the TCP that must stay clear of every face
slow_zone = 60            # mm: moving toward a face, speed falls linearly to 10 % of the cap over this
joints = { j2 = [-120, 120], j4 = [-140, 140] }            # soft limits, degrees, inside the arm's own
singularity = { slow = 17, stop = 30 }                     # condition number κ (these defaults)

[[arms.cell3.fence.keep_out]]
name = "table"
min = [250, -400, -100]
max = [900, 400, 80]

[arms.bench]
modbus = "10.0.0.5:1502"
"#;

/// `FENCED` with its line `was` written `now` (an empty `now` drops the line).
fn with(was: &str, now: &str) -> String {
    assert!(FENCED.contains(was), "{was}");
    let now = if now.is_empty() {
        String::new()
    } else {
        format!("{now}\n")
    };
    FENCED.replacen(&format!("{was}\n"), &now, 1)
}

/// Each mistake the issue names, and some more: the file as changed, its line, what is said.
fn mistakes() -> Vec<(String, usize, &'static str)> {
    let inside = "inside = { min = [-600, -600, 0], max = [800, 600, 900] }  # the box the tool \
                  stays in: mm, base frame";
    let radius = "tool_radius = 40          # mm: the sphere around the TCP that must stay clear \
                  of every face";
    let slow = "slow_zone = 60            # mm: moving toward a face, speed falls linearly to 10 \
                % of the cap over this";
    let joints = "joints = { j2 = [-120, 120], j4 = [-140, 140] }            # soft limits, \
                  degrees, inside the arm's own";
    let kappa = "singularity = { slow = 17, stop = 30 }                     # condition number κ \
                 (these defaults)";
    vec![
        (
            with(
                inside,
                "inside = { min = [-600, -600, 900], max = [800, 600, 900] }",
            ),
            6,
            "arms.cell3.fence.inside: min 900 is not below max 900 on z",
        ),
        (
            with("min = [250, -400, -100]", "min = [250, -400, 900]"),
            12,
            "arms.cell3.fence.keep_out[1]: min 900 is not below max 80 on z",
        ),
        (
            with(radius, "tool_radius = nan"),
            7,
            "arms.cell3.fence.tool_radius: NaN is not a finite number",
        ),
        (
            with("max = [900, 400, 80]", "max = [900, inf, 80]"),
            15,
            "arms.cell3.fence.keep_out[1].max: inf is not a finite number",
        ),
        (
            with(
                inside,
                "inside = { min = [-600, -600, -inf], max = [800, 600, 900] }",
            ),
            6,
            "arms.cell3.fence.inside.min: -inf is not a finite number",
        ),
        (
            with(radius, "tool_radius = -5"),
            7,
            "arms.cell3.fence.tool_radius: -5 is negative",
        ),
        (
            with(slow, "slow_zon = 60"),
            8,
            "unknown key 'slow_zon'; did you mean 'slow_zone'?",
        ),
        (
            with("name = \"table\"", "name = \"table\"\nenable = false"),
            14,
            "unknown key 'enable'; did you mean 'enabled'?",
        ),
        (
            with("name = \"table\"", "nmae = \"table\""),
            13,
            "unknown key 'nmae'; did you mean 'name'?",
        ),
        (
            with(joints, "joints = { j2 = [-120, 120], j8 = [-140, 140] }"),
            9,
            "arms.cell3.fence.joints.j8: the arm has joints j1 to j7",
        ),
        (
            with(joints, "joints = { j2 = [-120, 120], j4 = [-150, 140] }"),
            9,
            "arms.cell3.fence.joints.j4: [-150, 140] is outside the arm's own limits of ±147.8°",
        ),
        (
            with("name = \"table\"", ""),
            12,
            "arms.cell3.fence.keep_out[1].name: a zone needs a name",
        ),
        (
            with("min = [250, -400, -100]", "min = [250, -400]"),
            14,
            "arms.cell3.fence.keep_out[1].min: expected 3 numbers [x, y, z], found 2",
        ),
        (
            with(joints, "joints = { j2 = [-120] }"),
            9,
            "arms.cell3.fence.joints.j2: expected 2 numbers [min, max], found 1",
        ),
        (
            with(kappa, "singularity = { slow = 30, stop = 17 }"),
            10,
            "arms.cell3.fence.singularity: slow 30 must be at least 1 and below stop 17",
        ),
        (
            with(kappa, "singularity = { slow = 17, stpo = 30 }"),
            10,
            "unknown key 'stpo'; did you mean 'stop'?",
        ),
        (
            with(radius, "tool_radius = \"40 mm\""),
            7,
            "arms.cell3.fence.tool_radius: expected a number, found a string",
        ),
        (
            with("[arms.cell3.fence]", "[arms.cell3.fense]"),
            5,
            "unknown key 'fense'; did you mean 'fence'?",
        ),
    ]
}

#[test]
fn every_mistake_in_a_fence_is_named_by_its_line_and_key() {
    assert!(parse(FENCED).is_ok(), "{:?}", parse(FENCED));
    for (text, line, says) in mistakes() {
        assert_eq!(
            error(&text),
            format!("config.toml:{line}: {says}"),
            "{text}"
        );
    }
}

#[test]
fn a_second_zone_and_table_forms_are_named_by_their_own_lines() {
    let two = format!(
        "{}\n[[arms.cell3.fence.keep_out]]\nname = \"vice\"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n",
        FENCED
    );
    assert!(parse(&two).is_ok(), "{:?}", parse(&two));
    let again = two.replace("\"vice\"", "\"table\"");
    assert_eq!(
        error(&again),
        "config.toml:21: arms.cell3.fence.keep_out[2].name: a second zone named 'table'"
    );
    let flat = two.replace("max = [1, 1, 1]", "max = [1, 1, 0]");
    assert_eq!(
        error(&flat),
        "config.toml:20: arms.cell3.fence.keep_out[2]: min 0 is not below max 0 on z"
    );
    // Joints as a table of their own: each limit on its line.
    let joints = "[arms.arm]\n[arms.arm.fence.joints]\nj1 = [-170, 170]\nj6 = [-121, 0]\n";
    assert_eq!(
        error(joints),
        "config.toml:4: arms.arm.fence.joints.j6: [-121, 0] is outside the arm's own limits of \
         ±120.3°"
    );
    // `j02` is not how the arm names J2.
    assert_eq!(
        error("[arms.arm.fence]\njoints = { j02 = [-1, 1] }\n"),
        "config.toml:2: arms.arm.fence.joints.j02: the arm has joints j1 to j7"
    );
    assert_eq!(
        error("[arms.arm]\nfence = 3\n"),
        "config.toml:2: arms.arm.fence: expected a table, found an integer"
    );
    assert_eq!(
        error("[arms.arm.fence]\ninside = { min = [0, 0, 0] }\n"),
        "config.toml:2: arms.arm.fence.inside.max: missing (a box has a min and a max)"
    );
    assert_eq!(
        error("[arms.arm.fence]\ninside = { min = [0, \"1\", 0], max = [1, 1, 1] }\n"),
        "config.toml:2: arms.arm.fence.inside.min: expected 3 numbers [x, y, z], found a \
         string among them"
    );
}

/// Through the binary: exit 2, the file, line and key, before anything connects, by `armjog
/// arms`, the console and `status` alike.
#[tokio::test(flavor = "multi_thread")]
async fn a_bad_fence_exits_2_naming_file_line_and_key_before_anything_connects() {
    for (text, line, says) in mistakes() {
        let (_dir, config) = config_file(&text);
        let run = armjog(&config, &[], &["arms"]).await;
        assert_eq!(run.code, 2, "{text}: {}{}", run.stdout, run.stderr);
        assert_eq!(
            run.stderr,
            format!("armjog: {}:{line}: {says}\n", config.display()),
            "{text}"
        );
    }
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("addr");
    let text = with("keymap = \"numpad\"", &format!("modbus = \"{addr}\""))
        .replace("tool_radius = 40 ", "tool_radius = -40");
    let (_dir, config) = config_file(&text);
    for args in [&["--arm", "cell3"][..], &["status", "--arm", "cell3"]] {
        let run = armjog(&config, &[], args).await;
        assert_eq!(run.code, 2, "{args:?}: {}{}", run.stdout, run.stderr);
        assert_eq!(
            run.stderr,
            format!(
                "armjog: {}:7: arms.cell3.fence.tool_radius: -40 is negative\n",
                config.display()
            ),
            "{args:?}"
        );
    }
    let accepted =
        tokio::time::timeout(std::time::Duration::from_millis(200), listener.accept()).await;
    assert!(accepted.is_err(), "something connected");
}

/// A fenced profile with no arm named runs on the simulated arm: `armjog arms` takes it.
#[tokio::test(flavor = "multi_thread")]
async fn arms_accepts_a_fence_on_the_simulated_arm_and_counts_its_zones() {
    let (_dir, config) = config_file(FENCED);
    let run = armjog(&config, &[], &["arms"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "cell3  the built-in simulated arm  fence: 1 keep-out zone\n\
         bench  modbus 10.0.0.5:1502\n"
    );
    let more = format!(
        "{FENCED}[[arms.cell3.fence.keep_out]]\nname = \"vice\"\nmin = [0, 0, 0]\n\
         max = [1, 1, 1]\nenabled = false\n[arms.bench.fence]\n"
    );
    let (_dir, config) = config_file(&more);
    let run = armjog(&config, &[], &["arms"]).await;
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(
        run.stdout,
        "cell3  the built-in simulated arm  fence: 2 keep-out zones, 1 off\n\
         bench  modbus 10.0.0.5:1502  fence: no keep-out zones\n"
    );
}

#[test]
fn the_chosen_arms_fence_is_handed_on_with_its_options() {
    let (_dir, config) = config_file(FENCED);
    let parsed = |arm: &str| -> Parsed {
        let args: Vec<OsString> = ["armjog", "--config"]
            .iter()
            .map(OsString::from)
            .chain([config.clone().into_os_string()])
            .chain(["--arm", arm].iter().map(OsString::from))
            .collect();
        profiles::parse_args(args).expect("parses")
    };
    let cell3 = parsed("cell3");
    assert_eq!(cell3.arm.as_deref(), Some("cell3"));
    assert_eq!(cell3.cli.console.keymap, "numpad");
    let fence = cell3.fence.expect("a fence");
    assert_eq!(fence.tool_radius, 40.0);
    assert_eq!(
        fence.keep_out,
        [KeepOut {
            name: "table".into(),
            zone: Aabb {
                min: [250.0, -400.0, -100.0],
                max: [900.0, 400.0, 80.0],
            },
            enabled: true,
        }]
    );
    assert_eq!(parsed("bench").fence, None);
}
