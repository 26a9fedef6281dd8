//! Teaching the fence from the console: the fence screen (its rows, its selection, a name being
//! typed) and the changes its keys make, pure. The app applies them (`screen.rs`) and writes the
//! fence into the profile (`Effect::SaveFence`).

use std::sync::Arc;

use super::fence_watch::FenceWatch;
use super::{KeyInput, Severity};
use crate::console::keymap::{KeyName, NamedKey};
use crate::link::fence::{Aabb, FACE_NAMES, Fence, FenceError, KeepOut};

const ENTER: KeyName = KeyName::named(NamedKey::Enter);
const ESC: KeyName = KeyName::named(NamedKey::Esc);
const UP: KeyName = KeyName::named(NamedKey::Up);
const DOWN: KeyName = KeyName::named(NamedKey::Down);
const BACKSPACE: KeyName = KeyName::named(NamedKey::Backspace);
const DELETE: KeyName = KeyName::named(NamedKey::Delete);
/// The fence key closes the screen it opened.
const FENCE_KEY: KeyName = KeyName::char('F');
/// A face's row, 0-5; the zones' rows follow.
const FACES: usize = 6;
/// What no fresh telemetry means here.
const NO_TOOL: &str = "no fresh telemetry: the tool's position is not known";

/// What a key on the fence screen asks of the app.
#[derive(Debug, Clone, PartialEq)]
pub enum Taught {
    Say(String, Severity),
    /// The fence changed (`change`, in words): write it into the profile.
    Write(String),
}

/// A new box's faces before any is taught, mm: beyond the Gen3's reach (902 mm) on every side
/// but the floor, which is the base's mounting plane.
const UNTAUGHT_BOX: Aabb = Aabb {
    min: [-1200.0, -1200.0, -200.0],
    max: [1200.0, 1200.0, 1400.0],
};
/// The longest zone or profile name typed here.
pub const MAX_NAME: usize = 40;

/// What a name typed on the fence screen is for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Naming {
    /// A zone between the two corners marked.
    Zone { a: [i64; 3], b: [i64; 3] },
    /// The profile a fence taught without one is written to.
    Profile,
}

/// The fence screen: the row selected, and a name being typed.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct FenceScreen {
    pub selected: usize,
    pub naming: Option<(Naming, String)>,
}

/// One row of the fence screen: a face of the box (0-5) or a zone (6 on).
#[derive(Debug, Clone, PartialEq)]
pub struct FenceRow {
    pub label: String,
    /// Where it is, whether it is kept, the tool sphere's distance to it.
    pub detail: String,
}

/// The rows: the box's six faces, then the zones.
pub fn rows(fence: &Fence, tool: Option<[f64; 3]>) -> Vec<FenceRow> {
    let mut rows = Vec::with_capacity(6 + fence.keep_out.len());
    let mut clearances = Vec::new();
    if let Some(tool) = tool {
        fence.barriers(tool, |b| clearances.push((b.name.to_string(), b.clearance)));
    }
    let away = |name: &str| {
        clearances
            .iter()
            .find(|(n, _)| n == name)
            .map_or(String::new(), |(_, c)| match *c {
                c if c < 0.0 => format!(", {:.0} mm in", -c),
                c => format!(", {c:.0} mm away"),
            })
    };
    for (axis, names) in FACE_NAMES.iter().enumerate() {
        for (high, name) in names.iter().enumerate() {
            let detail = match &fence.inside {
                Some(inside) => {
                    let at = if high == 1 { inside.max } else { inside.min }[axis];
                    let axis_name = ["x", "y", "z"][axis];
                    format!("{axis_name} = {at:.0} mm{}", away(name))
                }
                None => "not set".to_string(),
            };
            rows.push(FenceRow {
                label: format!("box {name}"),
                detail,
            });
        }
    }
    for zone in &fence.keep_out {
        let state = if zone.enabled { "kept" } else { "off" };
        rows.push(FenceRow {
            label: format!("zone {}", zone.name),
            detail: format!("{state}{}", away(&zone.name)),
        });
    }
    rows
}

/// The fence with face `face` (0-5: -X, +X, -Y, +Y, floor, ceiling) where the tool sphere at
/// `tool` (mm) touches it from inside; a first face starts the box beyond the arm's reach.
pub fn set_face(fence: &Fence, face: usize, tool: [f64; 3]) -> Result<Fence, FenceError> {
    let (axis, high) = (face / 2, face % 2 == 1);
    let mut inside = fence.inside.unwrap_or(UNTAUGHT_BOX);
    let r = fence.tool_radius;
    if high {
        inside.max[axis] = (tool[axis] + r).round();
    } else {
        inside.min[axis] = (tool[axis] - r).round();
    }
    let taught = Fence {
        inside: Some(inside),
        ..fence.clone()
    };
    taught.check()?;
    Ok(taught)
}

/// The fence with zone `index` kept or not.
pub fn toggle_zone(fence: &Fence, index: usize) -> Fence {
    let mut taught = fence.clone();
    if let Some(zone) = taught.keep_out.get_mut(index) {
        zone.enabled = !zone.enabled;
    }
    taught
}

/// The fence without zone `index`, and the zone (for undo).
pub fn delete_zone(fence: &Fence, index: usize) -> Option<(Fence, KeepOut)> {
    let mut taught = fence.clone();
    (index < taught.keep_out.len()).then(|| {
        let zone = taught.keep_out.remove(index);
        (taught, zone)
    })
}

/// The fence with a zone `name` between the corners `a` and `b` (mm, tool points marked).
pub fn add_zone(fence: &Fence, name: &str, a: [i64; 3], b: [i64; 3]) -> Result<Fence, FenceError> {
    let mut taught = fence.clone();
    let corner = |pick: fn(i64, i64) -> i64| std::array::from_fn(|i| pick(a[i], b[i]) as f64);
    taught.keep_out.push(KeepOut {
        name: name.trim().to_string(),
        zone: Aabb {
            min: corner(i64::min),
            max: corner(i64::max),
        },
        enabled: true,
    });
    taught.check()?;
    Ok(taught)
}

/// Whether `name` can be a profile's name: a TOML bare key, as `[arms.NAME]` writes it.
pub fn profile_name_ok(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= MAX_NAME
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
}

/// A tool point to the millimetre, as a corner is marked.
pub fn mark(tool: [f64; 3]) -> [i64; 3] {
    tool.map(|v| v.round() as i64)
}

impl FenceWatch {
    /// A key on the fence screen `open`, the tool at `tool` (mm; `None` without fresh
    /// telemetry), `named`: the console runs on a profile. The screen as it stays (`None`:
    /// closed) and what the app is to say and write. A change is kept at once.
    pub fn on_key(
        &mut self,
        mut open: FenceScreen,
        key: &KeyInput,
        tool: Option<[f64; 3]>,
        named: bool,
    ) -> (Option<FenceScreen>, Vec<Taught>) {
        let mut taught = Vec::new();
        let mut say = |text: String, severity| taught.push(Taught::Say(text, severity));
        if let Some((naming, mut text)) = open.naming.take() {
            match key.key {
                ESC => say("cancelled".into(), Severity::Info),
                ENTER => return self.named(naming, text.trim(), open, named),
                BACKSPACE => {
                    text.pop();
                    open.naming = Some((naming, text));
                }
                _ => {
                    if let Some(c) = key.text.filter(|c| !c.is_control())
                        && text.chars().count() < MAX_NAME
                    {
                        text.push(c);
                    }
                    open.naming = Some((naming, text));
                }
            }
            return (Some(open), taught);
        }
        let fence = self.kept.as_deref().cloned().unwrap_or_default();
        let zone = open.selected.checked_sub(FACES);
        let change = match (key.key, key.text) {
            (ESC | FENCE_KEY, _) => return (None, taught),
            (UP, _) => {
                open.selected = open.selected.saturating_sub(1);
                None
            }
            (DOWN, _) => {
                open.selected = (open.selected + 1).min(FACES - 1 + fence.keep_out.len());
                None
            }
            (ENTER, _) | (_, Some('s')) if zone.is_none() => match tool {
                None => {
                    say(NO_TOOL.into(), Severity::Warning);
                    None
                }
                Some(tool) => match set_face(&fence, open.selected, tool) {
                    Ok(face_set) => {
                        let face = FACE_NAMES[open.selected / 2][open.selected % 2];
                        Some((face_set, format!("box {face} set at the tool")))
                    }
                    Err(e) => {
                        say(format!("not set: {e}"), Severity::Warning);
                        None
                    }
                },
            },
            (_, Some('e')) if let Some(i) = zone.filter(|i| *i < fence.keep_out.len()) => {
                let toggled = toggle_zone(&fence, i);
                let zone = &toggled.keep_out[i];
                let state = if zone.enabled { "kept" } else { "off" };
                let change = format!("zone {} {state}", zone.name);
                Some((toggled, change))
            }
            (DELETE, _) | (_, Some('x')) if let Some(i) = zone => {
                delete_zone(&fence, i).map(|(without, gone)| {
                    let change = format!("zone {} deleted (u brings it back)", gone.name);
                    self.deleted = Some((i, gone));
                    open.selected = open.selected.min(FACES - 1 + without.keep_out.len());
                    (without, change)
                })
            }
            (_, Some('u')) => match self.deleted.take() {
                Some((i, zone)) => {
                    let mut back = fence.clone();
                    let change = format!("zone {} back", zone.name);
                    back.keep_out.insert(i.min(back.keep_out.len()), zone);
                    Some((back, change))
                }
                None => {
                    say("no zone deleted to bring back".into(), Severity::Info);
                    None
                }
            },
            (_, Some('c')) => {
                match (tool, self.corner.take()) {
                    (None, corner) => {
                        self.corner = corner;
                        say(NO_TOOL.into(), Severity::Warning);
                    }
                    (Some(tool), None) => {
                        let [x, y, z] = mark(tool);
                        self.corner = Some([x, y, z]);
                        let text = format!(
                            "corner 1 at {x} {y} {z} mm: jog to the opposite corner, then F and c"
                        );
                        say(text, Severity::Info);
                    }
                    (Some(tool), Some(a)) => {
                        let b = mark(tool);
                        open.naming = Some((Naming::Zone { a, b }, String::new()));
                    }
                }
                None
            }
            _ => None,
        };
        if let Some((fence, change)) = change {
            taught.extend(self.teach(fence, change, &mut open, named));
        }
        (Some(open), taught)
    }

    /// A name typed on the fence screen: a zone's, or the profile a fence is written to.
    fn named(
        &mut self,
        naming: Naming,
        name: &str,
        mut open: FenceScreen,
        named: bool,
    ) -> (Option<FenceScreen>, Vec<Taught>) {
        let warn = |text: String| vec![Taught::Say(text, Severity::Warning)];
        let taught = match naming {
            Naming::Zone { a, b } => {
                let fence = self.kept.as_deref().cloned().unwrap_or_default();
                match add_zone(&fence, name, a, b) {
                    Ok(with_zone) => {
                        open.selected = FACES - 1 + with_zone.keep_out.len();
                        let change = format!("zone {name} added");
                        self.teach(with_zone, change, &mut open, named)
                    }
                    Err(e) => {
                        self.corner = Some(a);
                        warn(format!("zone not added: {e}"))
                    }
                }
            }
            Naming::Profile if profile_name_ok(name) => {
                self.profile = Some(name.to_string());
                vec![Taught::Write(format!("profile {name} made"))]
            }
            Naming::Profile => {
                open.naming = Some((Naming::Profile, name.to_string()));
                warn("a profile name is letters, digits, - and _ (e.g. cell3)".into())
            }
        };
        (Some(open), taught)
    }

    /// `fence` kept from now on (judged afresh at the next sample), and written into the
    /// profile, once named.
    fn teach(
        &mut self,
        fence: Fence,
        change: String,
        open: &mut FenceScreen,
        named: bool,
    ) -> Vec<Taught> {
        self.kept = Some(Arc::new(fence));
        self.verdict = None;
        if !named && self.profile.is_none() {
            open.naming = Some((Naming::Profile, String::new()));
            let text = format!("{change}: name the profile to write it into");
            return vec![Taught::Say(text, Severity::Info)];
        }
        vec![Taught::Write(change)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(r: f64) -> Fence {
        Fence {
            tool_radius: r,
            ..Fence::default()
        }
    }

    #[test]
    fn a_first_face_starts_the_box_beyond_reach_and_touches_the_sphere() {
        let taught = set_face(&sphere(40.0), 4, [456.6, 1.0, 433.8]).expect("a floor");
        let inside = taught.inside.expect("a box");
        // The floor 40 mm under the tool point; the rest as untaught.
        assert_eq!(inside.min, [-1200.0, -1200.0, 394.0]);
        assert_eq!(inside.max, UNTAUGHT_BOX.max);
        let ceiling = set_face(&taught, 5, [456.6, 1.0, 433.8]).expect("a ceiling");
        assert_eq!(ceiling.inside.expect("box").max[2], 474.0);
    }

    #[test]
    fn a_face_past_its_opposite_is_refused_naming_the_box() {
        let floor = set_face(&sphere(40.0), 4, [0.0, 0.0, 500.0]).expect("floor at 460");
        // A ceiling at 430 would be under the floor.
        let err = set_face(&floor, 5, [0.0, 0.0, 390.0]).expect_err("ceiling under floor");
        assert_eq!(err.to_string(), "inside: min 460 is not below max 430 on z");
    }

    #[test]
    fn a_zone_spans_its_two_corners_whichever_order_and_needs_depth_and_a_new_name() {
        let fence = add_zone(
            &Fence::default(),
            " table ",
            [900, 400, 80],
            [250, -400, -100],
        )
        .expect("a zone");
        let zone = &fence.keep_out[0];
        assert_eq!(zone.name, "table");
        assert_eq!(zone.zone.min, [250.0, -400.0, -100.0]);
        assert_eq!(zone.zone.max, [900.0, 400.0, 80.0]);
        assert!(add_zone(&fence, "flat", [0, 0, 80], [100, 100, 80]).is_err());
        let twice = add_zone(&fence, "table", [0, 0, 0], [1, 1, 1]).expect_err("a second table");
        assert_eq!(
            twice.to_string(),
            "keep_out[2].name: a second zone named 'table'"
        );
    }

    #[test]
    fn rows_list_the_faces_then_the_zones_with_the_sphere_s_distance() {
        let fence = add_zone(&sphere(40.0), "table", [250, -400, -100], [900, 400, 284])
            .and_then(|f| set_face(&f, 4, [0.0, 0.0, 40.0]))
            .expect("fence");
        let rows = rows(&toggle_zone(&fence, 0), Some([456.6, 1.0, 433.8]));
        assert_eq!(rows.len(), 7);
        assert_eq!(rows[4].label, "box floor");
        assert_eq!(rows[4].detail, "z = 0 mm, 394 mm away");
        // Off: kept in the file, no distance.
        assert_eq!(rows[6].label, "zone table");
        assert_eq!(rows[6].detail, "off");
        // Inside the table, 84 mm under its top: the sphere 124 mm in.
        let inside = super::rows(&fence, Some([500.0, 0.0, 200.0]));
        assert_eq!(inside[6].detail, "kept, 124 mm in");
        let (without, zone) = delete_zone(&fence, 0).expect("deleted");
        assert!(without.keep_out.is_empty() && zone.name == "table");
    }
}
