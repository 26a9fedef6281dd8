//! The fence in the state machine, on a fake clock: telemetry goes straight in, and the effects
//! are what the driver would be given. The rules' own figures are in `src/link/fence/tests.rs`.

use std::sync::Arc;
use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Effect, Input};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::console::view::View;
use armjog::kortex::gen3::{HOME_DEG, condition_number};
use armjog::kortex::{Coded, RegisterImage, RobotState, Telemetry};
use armjog::link::fence::{Aabb, Fence, KeepOut};
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus, TelemetrySource};

use crate::app_support::{STOP, config, jog, key, message, no_motion, press, release};

/// The tool point the telemetry reports, mm (over home's angles): 140 mm clear of the table.
const TOOL: [f64; 3] = [450.0, 0.0, 400.0];

/// A table with its top at z = 220 mm, a 40 mm sphere, the 60 mm slow zone.
fn fence() -> Fence {
    Fence {
        tool_radius: 40.0,
        keep_out: vec![KeepOut {
            name: "table".into(),
            zone: Aabb {
                min: [0.0, -400.0, -100.0],
                max: [900.0, 400.0, 220.0],
            },
            enabled: true,
        }],
        ..Fence::default()
    }
}

/// The arm at home with its tool point at `tool` mm.
fn at(tool: [f64; 3]) -> Input {
    let mut t = Telemetry::decode(&RegisterImage::default());
    t.robot_state = Coded::Known(RobotState::Ready);
    for (joint, q) in t.joints.iter_mut().zip(HOME_DEG) {
        joint.position = q as f32;
    }
    t.tcp.pose.x = (tool[0] / 1000.0) as f32;
    t.tcp.pose.y = (tool[1] / 1000.0) as f32;
    t.tcp.pose.z = (tool[2] / 1000.0) as f32;
    Input::Arm(ArmEvent::Telemetry(Box::new(t)))
}

/// An app on `config`, its link up at 50 %, Modbus telemetry at the tool point `tool`.
fn up(config: AppConfig, tool: Option<[f64; 3]>) -> (App, Instant) {
    let mut app = App::new(config, PositionBook::new());
    let t0 = Instant::now();
    let up = LinkStatus::Up {
        description: "test".into(),
    };
    app.handle(Input::Arm(ArmEvent::Status(up)), t0);
    app.handle(Input::Arm(ArmEvent::Speed(50)), t0);
    let source = TelemetrySource::Modbus;
    app.handle(Input::Arm(ArmEvent::TelemetrySource(source)), t0);
    if let Some(tool) = tool {
        app.handle(at(tool), t0);
    }
    (app, t0)
}

/// An app with `fence`, its link up, its tool at `tool`.
fn fenced(fence: Fence, tool: Option<[f64; 3]>) -> (App, Instant) {
    let config = AppConfig {
        fence: Some(Arc::new(fence)),
        ..config()
    };
    up(config, tool)
}

fn fence_speed(permille: u16) -> Effect {
    Effect::Arm(ArmCommand::FenceSpeed(permille))
}

#[test]
fn home_is_far_from_the_default_singularity_slow_down() {
    let kappa = condition_number(&HOME_DEG.map(f64::to_radians));
    assert!(kappa < 17.0, "κ at home {kappa}");
}

#[test]
fn in_the_slow_zone_the_share_goes_out_before_the_jog_and_the_whole_speed_after_the_stop() {
    // The sphere 30 mm over the table: 0.1 + 0.9 * 30 / 60 = 0.55.
    let (mut app, t0) = fenced(fence(), Some([450.0, 0.0, 290.0]));
    let effects = press(&mut app, "f", t0);
    assert_eq!(effects, [fence_speed(550), jog(0, 0, -1)]);
    let status = View::new(&app).arm.fence;
    assert_eq!(status.as_deref(), Some("SLOWED: table 30 mm"));
    // Going up is away from it: the whole speed, no share.
    let effects = release(&mut app, "f", t0);
    assert_eq!(effects, [STOP, fence_speed(1000)]);
    let effects = press(&mut app, "r", t0);
    assert_eq!(effects, [jog(0, 0, 1)]);
}

#[test]
fn each_sample_nearer_the_table_sends_the_lower_share_and_contact_stops_with_the_key_held() {
    let (mut app, t0) = fenced(fence(), Some(TOOL));
    assert_eq!(press(&mut app, "f", t0), [jog(0, 0, -1)]);
    let t1 = t0 + Duration::from_millis(33);
    // 15 mm clear: 0.325, kept to 0.30.
    let effects = app.handle(at([450.0, 0.0, 275.0]), t1);
    assert_eq!(effects, [fence_speed(300), jog(0, 0, -1)]);
    // The same again: nothing new goes out.
    let t2 = t1 + Duration::from_millis(33);
    assert!(app.handle(at([450.0, 0.0, 275.0]), t2).is_empty());
    // 0.5 mm clear: contact. A STOP, and the speed put back; the key still held.
    let t3 = t2 + Duration::from_millis(33);
    let effects = app.handle(at([450.0, 0.0, 260.5]), t3);
    assert_eq!(effects, [STOP, fence_speed(1000)]);
    assert!(app.jog().is_jogging());
    let status = View::new(&app).arm.fence;
    assert_eq!(status.as_deref(), Some("AT FENCE: table"));
    // Its refreshes send nothing while it stays there.
    let t4 = t3 + Duration::from_millis(150);
    assert!(no_motion(&app.handle(Input::Tick, t4)));
    // +X as well: the tool slides, -Z taken out.
    let effects = app.handle(key("w", KeyKind::Press), t4);
    assert_eq!(effects, [jog(1, 0, 0)]);
}

#[test]
fn a_step_into_the_table_is_refused_and_nothing_moves() {
    // 40 mm clear: a 50 mm step down would put the sphere 10 mm in.
    let (mut app, t0) = fenced(fence(), Some([450.0, 0.0, 300.0]));
    press(&mut app, "t", t0);
    release(&mut app, "t", t0);
    // The step size up to 50 mm: 5 mm, 10, 50.
    for _ in 0..2 {
        press(&mut app, ".", t0);
        release(&mut app, ".", t0);
    }
    let effects = press(&mut app, "f", t0);
    assert!(no_motion(&effects), "{effects:?}");
    assert!(message(&app).contains("table"), "{}", message(&app));
}

#[test]
fn with_a_fence_and_no_telemetry_yet_nothing_moves_and_the_reason_is_said() {
    let (mut app, t0) = fenced(fence(), None);
    let effects = press(&mut app, "w", t0);
    assert!(no_motion(&effects), "{effects:?}");
    assert_eq!(
        message(&app),
        "refused: no fresh telemetry for the fence to see the tool by"
    );
}

#[test]
fn a_tool_already_in_a_zone_is_said_at_rest_and_may_only_go_out() {
    // 12 mm under the table's top: the sphere 52 mm in.
    let (mut app, t0) = fenced(fence(), Some([450.0, 0.0, 208.0]));
    let status = View::new(&app).arm.fence;
    assert_eq!(status.as_deref(), Some("OUTSIDE FENCE: table, 52 mm in"));
    assert!(no_motion(&press(&mut app, "f", t0)));
    release(&mut app, "f", t0);
    assert_eq!(press(&mut app, "r", t0), [fence_speed(100), jog(0, 0, 1)]);
}

/// Types `text` into the app, a key a character.
fn type_text(app: &mut App, text: &str, now: Instant) {
    for c in text.chars() {
        app.handle(
            Input::Key(armjog::console::app::KeyInput {
                key: if c == ' ' {
                    "space".to_string()
                } else {
                    c.to_string()
                }
                .parse()
                .expect("a key"),
                text: Some(c),
                kind: KeyKind::Press,
            }),
            now,
        );
    }
}

/// The fence an effect writes, and to which profile and file.
fn saved(effects: &[Effect]) -> Option<(String, Fence, String)> {
    effects.iter().find_map(|e| match e {
        Effect::SaveFence(change) => Some((
            change.arm.clone(),
            change.fence.clone(),
            change.change.clone(),
        )),
        _ => None,
    })
}

/// An app on a profile `cell` in `config.toml`, its tool at `tool`.
fn teaching(fence: Fence, tool: [f64; 3]) -> (App, Instant) {
    let config = AppConfig {
        fence: Some(Arc::new(fence)),
        arm_name: Some("cell".into()),
        config_file: Some("config.toml".into()),
        ..config()
    };
    up(config, Some(tool))
}

#[test]
fn the_floor_is_set_at_the_tool_and_written_into_the_profile() {
    let (mut app, t0) = teaching(fence(), [450.0, 0.0, 400.0]);
    press(&mut app, "F", t0);
    // Rows: -X, +X, -Y, +Y, floor, ceiling, then the zones.
    for _ in 0..4 {
        press(&mut app, "down", t0);
    }
    let effects = press(&mut app, "s", t0);
    let (arm, taught, change) = saved(&effects).expect("the fence written");
    assert_eq!(
        (arm.as_str(), change.as_str()),
        ("cell", "box floor set at the tool")
    );
    let inside = taught.inside.expect("a box");
    // The sphere's bottom: 400 - 40.
    assert_eq!(inside.min[2], 360.0);
    // Kept at once: the screen lists it, and a jog down is judged against it.
    let rows = View::new(&app).arm.fence_screen.expect("open").rows;
    assert_eq!(rows[4].detail, "z = 360 mm, 0 mm away");
    app.handle(Input::FenceSaved(Ok(())), t0);
    assert_eq!(message(&app), "fence written to the profile");
    press(&mut app, "esc", t0);
    assert!(no_motion(&press(&mut app, "f", t0)));
}

#[test]
fn a_zone_is_made_from_two_corners_and_named_then_turned_off_deleted_and_brought_back() {
    let (mut app, t0) = teaching(Fence::default(), [450.0, 0.0, 400.0]);
    press(&mut app, "F", t0);
    press(&mut app, "c", t0);
    assert!(
        message(&app).starts_with("corner 1 at 450 0 400 mm"),
        "{}",
        message(&app)
    );
    press(&mut app, "esc", t0);
    // Jogged (here: reported) to the opposite corner.
    app.handle(at([550.0, 100.0, 300.0]), t0 + Duration::from_millis(33));
    press(&mut app, "F", t0);
    press(&mut app, "c", t0);
    type_text(&mut app, "camera", t0);
    let effects = press(&mut app, "enter", t0);
    let (_, taught, change) = saved(&effects).expect("written");
    assert_eq!(change, "zone camera added");
    let zone = &taught.keep_out[0];
    assert_eq!(
        (zone.zone.min, zone.zone.max),
        ([450.0, 0.0, 300.0], [550.0, 100.0, 400.0])
    );
    // The new zone is selected: off, deleted, back.
    let (_, off, _) = saved(&press(&mut app, "e", t0)).expect("written");
    assert!(!off.keep_out[0].enabled);
    let (_, gone, change) = saved(&press(&mut app, "x", t0)).expect("written");
    assert!(gone.keep_out.is_empty());
    assert_eq!(change, "zone camera deleted (u brings it back)");
    let (_, back, _) = saved(&press(&mut app, "u", t0)).expect("written");
    assert_eq!(back.keep_out[0].name, "camera");
}

#[test]
fn taught_without_a_profile_it_asks_for_a_name_and_a_failed_write_is_marked() {
    let config = AppConfig {
        config_file: Some("config.toml".into()),
        ..config()
    };
    let (mut app, t0) = up(config, Some([450.0, 0.0, 400.0]));
    press(&mut app, "F", t0);
    let asked = press(&mut app, "s", t0);
    assert!(saved(&asked).is_none());
    assert!(
        message(&app).contains("name the profile"),
        "{}",
        message(&app)
    );
    type_text(&mut app, "bad name", t0);
    press(&mut app, "enter", t0);
    assert!(
        message(&app).contains("letters, digits"),
        "{}",
        message(&app)
    );
    for _ in 0.."bad name".len() {
        press(&mut app, "backspace", t0);
    }
    type_text(&mut app, "bench2", t0);
    let (arm, taught, _) = saved(&press(&mut app, "enter", t0)).expect("written");
    assert_eq!(arm, "bench2");
    assert_eq!(taught.inside.expect("box").min[0], 450.0 - 0.0);
    app.handle(Input::FenceSaved(Err("config.toml: read-only".into())), t0);
    assert_eq!(
        message(&app),
        "fence NOT written: config.toml: read-only; kept for this session"
    );
    let view = View::new(&app).arm.fence_screen.expect("open");
    assert_eq!(view.unwritten.as_deref(), Some("config.toml: read-only"));
}

/// Criterion 6: a zone taught in the console is in config.toml with the file's comments kept,
/// and the next start, reading the profile, keeps it: a step into it is refused.
#[test]
fn a_zone_taught_is_written_with_the_comments_kept_and_holds_at_the_next_start() {
    let dir = tempfile::tempdir().expect("a folder");
    let file = dir.path().join("config.toml");
    let text = "# the cell by the window\n[arms.cell]\n";
    std::fs::write(&file, text).expect("written");
    let config = AppConfig {
        arm_name: Some("cell".into()),
        config_file: Some(file.clone()),
        ..config()
    };
    let (mut app, t0) = up(config, Some([450.0, 0.0, 200.0]));
    press(&mut app, "F", t0);
    press(&mut app, "c", t0);
    press(&mut app, "esc", t0);
    app.handle(at([650.0, 200.0, 100.0]), t0);
    press(&mut app, "F", t0);
    press(&mut app, "c", t0);
    type_text(&mut app, "fixture", t0);
    let effects = press(&mut app, "enter", t0);
    let Some(Effect::SaveFence(change)) = effects
        .into_iter()
        .find(|e| matches!(e, Effect::SaveFence(_)))
    else {
        panic!("the fence is written");
    };
    // What the runtime does with the effect.
    let save = armjog::console::fence_file::FenceSave {
        file: change.file.clone(),
        arm: change.arm.clone(),
        fence: change.fence.clone(),
        new_profile: change.new_profile.clone(),
    };
    armjog::console::fence_file::write_fence(&save).expect("written");
    let written = std::fs::read_to_string(&file).expect("read");
    assert!(
        written.starts_with("# the cell by the window\n[arms.cell]\n"),
        "{written}"
    );
    assert!(written.contains("name = \"fixture\""), "{written}");

    // The next start: the profile read as `armjog --arm cell` reads it.
    let profiles = armjog::cli::profiles::parse(&file, &written).expect("a valid profile");
    let fence = profiles
        .get("cell")
        .expect("cell")
        .fence
        .clone()
        .expect("a fence");
    assert_eq!(fence, change.fence);
    let (mut next, t1) = teaching(fence, [450.0, 0.0, 400.0]);
    // A 50 mm step down from 40 mm over the zone's top (200; no sphere taught): into it.
    press(&mut next, "t", t1);
    for _ in 0..2 {
        press(&mut next, ".", t1);
    }
    next.handle(at([550.0, 100.0, 240.0]), t1);
    assert!(no_motion(&press(&mut next, "f", t1)));
    assert!(message(&next).contains("fixture"), "{}", message(&next));
}

#[test]
fn a_fence_slow_down_the_link_refuses_stops_the_jog() {
    // 30 mm over the table: the share goes out before the jog.
    let (mut app, t0) = fenced(fence(), Some([450.0, 0.0, 290.0]));
    assert_eq!(press(&mut app, "f", t0), [fence_speed(550), jog(0, 0, -1)]);
    let failed = ArmEvent::Failed {
        command: armjog::link::interface::CommandKind::FenceSpeed,
        error: armjog::link::interface::ArmError::NoTalosLink,
    };
    let effects = app.handle(Input::Arm(failed), t0);
    assert!(effects.contains(&STOP), "{effects:?}");
    assert!(!app.jog().is_jogging());
}
