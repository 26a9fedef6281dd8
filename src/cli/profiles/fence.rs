//! A profile's `[arms.NAME.fence]` table read into a [`Fence`]: the keys and the shape of each
//! value here; what the values may be is [`Fence::check`]'s, whose key names the line.

use std::borrow::Cow;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::ProfileError;
use super::file::{Locator, found};
use crate::link::fence::{Aabb, Fence, FenceError, KeepOut, Singularity};

type Key<'i> = Spanned<Cow<'i, str>>;
type Value<'i> = Spanned<DeValue<'i>>;

/// The keys of the fence table.
const FENCE_KEYS: [&str; 6] = [
    "inside",
    "tool_radius",
    "slow_zone",
    "joints",
    "singularity",
    "keep_out",
];
/// The keys of `inside`.
const BOX_KEYS: [&str; 2] = ["min", "max"];
/// The keys of a `[[...keep_out]]` zone.
const ZONE_KEYS: [&str; 4] = ["name", "min", "max", "enabled"];
/// The keys of `singularity`.
const SINGULARITY_KEYS: [&str; 2] = ["slow", "stop"];

/// Reads the value of `arm`'s (`arms.cell3`) `fence` key and checks it whole.
pub(super) fn read(
    at: &Locator,
    arm: &str,
    key: &Key<'_>,
    value: &Value<'_>,
) -> Result<Fence, ProfileError> {
    let path = format!("{arm}.fence");
    let table = table(at, &path, value)?;
    let mut fence = Fence::default();
    for (key, value) in table {
        let name = key.get_ref().as_ref();
        let at_key = format!("{path}.{name}");
        match name {
            "inside" => fence.inside = Some(read_box(at, &at_key, value, &BOX_KEYS)?.zone),
            "tool_radius" => fence.tool_radius = number(at, &at_key, value)?,
            "slow_zone" => fence.slow_zone = number(at, &at_key, value)?,
            "joints" => fence.joints = joints(at, &path, value)?,
            "singularity" => fence.singularity = singularity(at, &at_key, value)?,
            "keep_out" => fence.keep_out = keep_out(at, &at_key, value)?,
            _ => return Err(at.unknown_key(key, &names(&FENCE_KEYS))),
        }
    }
    fence.check().map_err(|e| {
        let line = line_of(at, at.line(&key.span()), value.get_ref(), e.key());
        at.error(line, format!("{path}.{e}"))
    })?;
    Ok(fence)
}

/// The line of the dotted `key` (`keep_out[2].min`) in the fence table `fence` (at `fence_line`):
/// the line of as much of it as the file writes (a zone without a name: the zone's).
fn line_of(at: &Locator, fence_line: usize, fence: &DeValue<'_>, key: &str) -> usize {
    let mut line = fence_line;
    let mut here = fence;
    for part in key.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((name, rest)) => (
                name,
                rest.strip_suffix(']').and_then(|i| i.parse::<usize>().ok()),
            ),
            None => (part, None),
        };
        let DeValue::Table(table) = here else { break };
        let Some((key, value)) = table.iter().find(|(k, _)| k.get_ref() == name) else {
            break;
        };
        line = at.line(&key.span());
        here = value.get_ref();
        // `keep_out[1]`: the first zone, its `[[...]]` header or its `{`.
        if let Some(n) = index {
            let zone = match here {
                DeValue::Array(items) => n.checked_sub(1).and_then(|i| items.get(i)),
                _ => None,
            };
            let Some(zone) = zone else { break };
            line = at.line(&zone.span());
            here = zone.get_ref();
        }
    }
    line
}

fn names(keys: &[&str]) -> Vec<String> {
    keys.iter().map(|k| k.to_string()).collect()
}

fn table<'v, 'i>(
    at: &Locator,
    path: &str,
    value: &'v Value<'i>,
) -> Result<&'v DeTable<'i>, ProfileError> {
    match value.get_ref() {
        DeValue::Table(table) => Ok(table),
        _ => Err(at.wrong_type(value, path, "a table")),
    }
}

/// An integer or a float as a number (`nan` and `inf` too: the check refuses them, by key).
fn as_number(value: &DeValue<'_>) -> Option<f64> {
    match value {
        DeValue::Integer(i) => i128::from_str_radix(i.as_str(), i.radix())
            .map(|i| i as f64)
            .ok()
            .or_else(|| (i.radix() == 10).then(|| i.as_str().parse().ok()).flatten()),
        DeValue::Float(f) => f.as_str().parse().ok(),
        _ => None,
    }
}

fn number(at: &Locator, path: &str, value: &Value<'_>) -> Result<f64, ProfileError> {
    as_number(value.get_ref()).ok_or_else(|| at.wrong_type(value, path, "a number"))
}

/// An array of exactly `N` numbers, `shape` naming them (`[x, y, z]`).
fn numbers<const N: usize>(
    at: &Locator,
    path: &str,
    value: &Value<'_>,
    shape: &str,
) -> Result<[f64; N], ProfileError> {
    let expected = format!("{N} numbers {shape}");
    let DeValue::Array(items) = value.get_ref() else {
        return Err(at.wrong_type(value, path, &expected));
    };
    let line = at.line(&value.span());
    if items.len() != N {
        let found = items.len();
        return Err(at.error(line, format!("{path}: expected {expected}, found {found}")));
    }
    let mut out = [0.0; N];
    for (slot, item) in out.iter_mut().zip(items.iter()) {
        *slot = as_number(item.get_ref()).ok_or_else(|| {
            let found = found(item.get_ref());
            at.error(
                line,
                format!("{path}: expected {expected}, found {found} among them"),
            )
        })?;
    }
    Ok(out)
}

/// A box's keys (`inside`'s, or a zone's with its name and switch), each read by its kind.
struct BoxKeys {
    zone: Aabb,
    name: Option<String>,
    enabled: Option<bool>,
}

/// The table at `path`, holding `min` and `max` and no key outside `known`.
fn read_box(
    at: &Locator,
    path: &str,
    value: &Value<'_>,
    known: &[&str],
) -> Result<BoxKeys, ProfileError> {
    let table = table(at, path, value)?;
    let (mut min, mut max, mut name, mut enabled) = (None, None, None, None);
    for (key, value) in table {
        let key_name = key.get_ref().as_ref();
        if !known.contains(&key_name) {
            return Err(at.unknown_key(key, &names(known)));
        }
        let at_key = format!("{path}.{key_name}");
        match key_name {
            "min" => min = Some(numbers::<3>(at, &at_key, value, "[x, y, z]")?),
            "max" => max = Some(numbers::<3>(at, &at_key, value, "[x, y, z]")?),
            "name" => match value.get_ref() {
                DeValue::String(s) => name = Some(s.to_string()),
                _ => return Err(at.wrong_type(value, &at_key, "a string")),
            },
            _ => match value.get_ref() {
                DeValue::Boolean(b) => enabled = Some(*b),
                _ => return Err(at.wrong_type(value, &at_key, "true or false")),
            },
        }
    }
    let missing = |which: &str| {
        at.error(
            at.line(&value.span()),
            format!("{path}.{which}: missing (a box has a min and a max)"),
        )
    };
    let zone = Aabb {
        min: min.ok_or_else(|| missing("min"))?,
        max: max.ok_or_else(|| missing("max"))?,
    };
    Ok(BoxKeys {
        zone,
        name,
        enabled,
    })
}

/// `joints = { j2 = [-120, 120] }`: soft limits by joint, `j1` to `j7`.
fn joints(
    at: &Locator,
    fence_path: &str,
    value: &Value<'_>,
) -> Result<[Option<[f64; 2]>; 7], ProfileError> {
    let mut joints = [None; 7];
    for (key, value) in table(at, &format!("{fence_path}.joints"), value)? {
        let name = key.get_ref().as_ref();
        // As written: `j02` is not `j2`, whose line a check would look for.
        let Some(index) = Fence::joint_index(name).filter(|i| format!("j{}", i + 1) == name) else {
            let e = FenceError::UnknownJoint {
                key: format!("joints.{name}"),
            };
            return Err(at.error(at.line(&key.span()), format!("{fence_path}.{e}")));
        };
        let path = format!("{fence_path}.joints.{name}");
        joints[index] = Some(numbers::<2>(at, &path, value, "[min, max]")?);
    }
    Ok(joints)
}

fn singularity(at: &Locator, path: &str, value: &Value<'_>) -> Result<Singularity, ProfileError> {
    let mut singularity = Singularity::default();
    for (key, value) in table(at, path, value)? {
        let name = key.get_ref().as_ref();
        let at_key = format!("{path}.{name}");
        match name {
            "slow" => singularity.slow = number(at, &at_key, value)?,
            "stop" => singularity.stop = number(at, &at_key, value)?,
            _ => return Err(at.unknown_key(key, &names(&SINGULARITY_KEYS))),
        }
    }
    Ok(singularity)
}

/// `[[arms.NAME.fence.keep_out]]` zones (or an array of inline tables), in the file's order.
fn keep_out(at: &Locator, path: &str, value: &Value<'_>) -> Result<Vec<KeepOut>, ProfileError> {
    let DeValue::Array(items) = value.get_ref() else {
        return Err(at.wrong_type(value, path, "an array of tables ([[...keep_out]])"));
    };
    let mut zones = Vec::with_capacity(items.len());
    for (index, item) in items.iter().enumerate() {
        let read = read_box(at, &format!("{path}[{}]", index + 1), item, &ZONE_KEYS)?;
        zones.push(KeepOut {
            // None: an empty name, which the check refuses naming the zone.
            name: read.name.unwrap_or_default(),
            zone: read.zone,
            enabled: read.enabled.unwrap_or(true),
        });
    }
    Ok(zones)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::cli::profiles::parse;

    /// The issue's example, as written there.
    const CELL3: &str = "\
[arms.cell3.fence]
inside = { min = [-600, -600, 0], max = [800, 600, 900] }  # the box the tool stays in: mm, base frame
tool_radius = 40          # mm: the sphere around the TCP that must stay clear of every face
slow_zone = 60            # mm: moving toward a face, speed falls linearly to 10 % of the cap over this
joints = { j2 = [-120, 120], j4 = [-140, 140] }            # soft limits, degrees, inside the arm's own
singularity = { slow = 17, stop = 30 }                     # condition number κ (these defaults)

[[arms.cell3.fence.keep_out]]
name = \"table\"
min = [250, -400, -100]
max = [900, 400, 80]
";

    #[test]
    fn the_issues_example_reads_into_its_fence() {
        let profiles = parse(Path::new("config.toml"), CELL3).expect("the example");
        let cell3 = profiles.get("cell3").expect("cell3");
        let mut joints = [None; 7];
        joints[1] = Some([-120.0, 120.0]);
        joints[3] = Some([-140.0, 140.0]);
        let expected = Fence {
            inside: Some(Aabb {
                min: [-600.0, -600.0, 0.0],
                max: [800.0, 600.0, 900.0],
            }),
            tool_radius: 40.0,
            slow_zone: 60.0,
            joints,
            singularity: Singularity {
                slow: 17.0,
                stop: 30.0,
            },
            keep_out: vec![KeepOut {
                name: "table".into(),
                zone: Aabb {
                    min: [250.0, -400.0, -100.0],
                    max: [900.0, 400.0, 80.0],
                },
                enabled: true,
            }],
        };
        assert_eq!(cell3.fence, Some(expected));
        // No console option came of it; the header is the profile's line.
        assert!(cell3.settings.is_empty());
        assert_eq!(cell3.line, 1);
    }

    #[test]
    fn every_key_is_optional_and_a_zone_may_be_off() {
        let text = "[arms.a]\ntalos = \"op\"\n[arms.a.fence]\n[arms.b]\nfence = { keep_out = [\
                    { name = \"vice\", min = [0, 0, 0], max = [1.5, 1, 1], enabled = false }] }\n";
        let profiles = parse(Path::new("config.toml"), text).expect("good");
        assert_eq!(profiles.get("a").expect("a").fence, Some(Fence::default()));
        let b = profiles
            .get("b")
            .expect("b")
            .fence
            .clone()
            .expect("a fence");
        assert_eq!(
            b.keep_out,
            [KeepOut {
                name: "vice".into(),
                zone: Aabb {
                    min: [0.0; 3],
                    max: [1.5, 1.0, 1.0],
                },
                enabled: false,
            }]
        );
        assert_eq!(b.zones().count(), 0);
        // No table, no fence.
        let none = parse(Path::new("config.toml"), "[arms.c]\nunit = 2\n").expect("good");
        assert_eq!(none.get("c").expect("c").fence, None);
    }
}
