//! A remembered position's name from a file reaches the simulator's log escaped and capped:
//! a name holding `\n`, `\r` and NUL cannot forge a log line, and a megabyte name is not
//! logged whole.

use armjog::sim::arm_model::Arm;
use armjog::sim::operator::{Operator, RememberedPosition};

use crate::log_capture;

fn remembered(name: &str) -> RememberedPosition {
    RememberedPosition {
        name: name.to_string(),
        position_m: [0.45, 0.0, 0.43],
        orientation_deg: None,
        joints_deg: None,
        parent: None,
        anchor: false,
    }
}

#[test]
fn a_hostile_name_is_logged_as_one_escaped_capped_line() {
    let log = log_capture::capture();
    let forged = "hostile-a\n2026-01-01T00:00:00.000000Z  INFO sim talos: forged\r\0";
    let huge = format!("hostile-b{}", "x".repeat(1 << 20));
    let restored =
        Operator::default().restore(&Arm::default(), vec![remembered(forged), remembered(&huge)]);
    assert_eq!(restored, 0, "neither name keeps the name rule");
    let text = log.text();
    let lines: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("hostile-a") || l.contains("hostile-b"))
        .collect();
    assert_eq!(lines.len(), 2, "one line per name: {lines:#?}");
    assert!(
        !text
            .lines()
            .any(|l| l.starts_with("2026-01-01T00:00:00.000000Z")),
        "no forged line"
    );
    let forged_line = lines
        .iter()
        .find(|l| l.contains("hostile-a"))
        .expect("logged");
    assert!(
        forged_line
            .contains("hostile-a\\n2026-01-01T00:00:00.000000Z  INFO sim talos: forged\\r\\0"),
        "{forged_line}"
    );
    assert!(!forged_line.contains('\0') && !forged_line.contains('\r'));
    let huge_line = lines
        .iter()
        .find(|l| l.contains("hostile-b"))
        .expect("logged");
    assert!(huge_line.len() < 1_000, "capped: {} bytes", huge_line.len());
    assert!(
        huge_line.contains("… (1048585 characters, 1048585 bytes)"),
        "{huge_line}"
    );
}
