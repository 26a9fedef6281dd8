//! The document edit: the fence's values merged into the file's tables, keeping what can be
//! kept (see the parent module's notes).

use toml_edit::{
    Array, ArrayOfTables, Decor, DocumentMut, InlineTable, Item, Table, TableLike, Value,
};

use super::tenth;
use crate::link::fence::{Aabb, Fence, KeepOut, Singularity};

/// A key on the way to the fence that holds something else than a table.
pub(super) struct NotATable {
    pub(super) path: Vec<String>,
    pub(super) found: &'static str,
}

/// Sets `arms.ARM.fence` in `document`, making `arms` and `arms.ARM` if missing.
pub(super) fn place(
    document: &mut DocumentMut,
    arm: &str,
    fence: &Fence,
    new_profile: &[(String, String)],
) -> Result<(), NotATable> {
    let after_all = last_position(document.as_item()).saturating_add(1);
    if document.as_table().is_empty() {
        // A file of comments alone: they head the file, not follow what is added.
        let comments = document.trailing().clone();
        document.set_trailing("");
        document.as_table_mut().decor_mut().set_prefix(comments);
    }
    let arms = document.as_table_mut().entry("arms").or_insert_with(|| {
        // `[arms.NAME]` headers make it; it has no header of its own.
        let mut arms = Table::new();
        arms.set_implicit(true);
        Item::Table(arms)
    });
    let path = ["arms".to_string(), arm.to_string(), "fence".to_string()];
    within(arms, &path[..1], |arms, standard| {
        let created = !arms.contains_key(arm);
        let arm_item = arms.entry(arm).or_insert_with(|| {
            if standard {
                // `[arms.NAME]`, after everything the file has.
                let mut table = Table::new();
                table.set_position(Some(after_all));
                Item::Table(table)
            } else {
                Item::Value(Value::InlineTable(InlineTable::new()))
            }
        });
        within(arm_item, &path[..2], |arm, standard| {
            // A profile made here gets the console's link settings (see `FenceSave`).
            for (key, text) in new_profile.iter().filter(|_| created) {
                arm.insert(key, Item::Value(setting(text)));
            }
            // A new `[arms.NAME.fence]` comes after the arm's table: it takes the place of the
            // table before it, toml_edit's rule for a table without one.
            let fence_item = arm.entry("fence").or_insert_with(|| {
                if standard {
                    Item::Table(Table::new())
                } else {
                    Item::Value(Value::InlineTable(InlineTable::new()))
                }
            });
            within(fence_item, &path, |table, standard| {
                merge_fence(table, standard, fence);
                Ok(())
            })
        })
    })
}

/// Runs `edit` on the table `item` (at `path`), telling it whether the table is standard;
/// an inline one keeps its closing spaces ([`edit_inline`]).
fn within<R>(
    item: &mut Item,
    path: &[String],
    edit: impl FnOnce(&mut dyn TableLike, bool) -> Result<R, NotATable>,
) -> Result<R, NotATable> {
    let standard = is_standard(item);
    match item {
        Item::Value(Value::InlineTable(table)) => edit_inline(table, |table| edit(table, false)),
        item => edit(table_like(item, path)?, standard),
    }
}

/// A table with a `[header]` of its own, under which `[[...]]` tables can go.
fn is_standard(item: &Item) -> bool {
    matches!(item, Item::Table(table) if !table.is_dotted())
}

/// The table `item` (at `path`), standard, dotted or inline.
fn table_like<'t>(item: &'t mut Item, path: &[String]) -> Result<&'t mut dyn TableLike, NotATable> {
    let found = kind(item);
    item.as_table_like_mut().ok_or_else(|| NotATable {
        path: path.to_vec(),
        found,
    })
}

/// What a value is, as an error names it (`an integer`).
fn kind(item: &Item) -> &'static str {
    match item {
        Item::None => "nothing",
        Item::Table(_) => "a table",
        Item::ArrayOfTables(_) => "an array of tables",
        Item::Value(value) => match value {
            Value::String(_) => "a string",
            Value::Integer(_) => "an integer",
            Value::Float(_) => "a float",
            Value::Boolean(_) => "a boolean",
            Value::Datetime(_) => "a date",
            Value::Array(_) => "an array",
            Value::InlineTable(_) => "a table",
        },
    }
}

/// The largest place of a table in the document (a new table placed after it comes last).
fn last_position(item: &Item) -> isize {
    let of_table = |table: &Table| {
        table
            .iter()
            .map(|(_, item)| last_position(item))
            .fold(table.position().unwrap_or(0), isize::max)
    };
    match item {
        Item::Table(table) => of_table(table),
        Item::ArrayOfTables(tables) => tables.iter().map(of_table).max().unwrap_or(0),
        Item::None | Item::Value(_) => 0,
    }
}

/// What a key of the fence is to hold. Numbers are the fence's own: a value the file writes as
/// the same number stays as written; a new one is written to a tenth ([`number`]).
#[derive(Debug, Clone, PartialEq)]
enum Want {
    Number(f64),
    Text(String),
    Switch(bool),
    List(Vec<Want>),
    Map(Vec<(String, Want)>),
}

fn corner(corner: [f64; 3]) -> Want {
    Want::List(corner.iter().map(|v| Want::Number(*v)).collect())
}

/// `{ min = [x, y, z], max = [x, y, z] }`.
fn aabb(aabb: &Aabb) -> Want {
    Want::Map(vec![
        ("min".into(), corner(aabb.min)),
        ("max".into(), corner(aabb.max)),
    ])
}

/// `{ j2 = [min, max], ... }`, the joints limited; none: `None`.
fn joints(joints: &[Option<[f64; 2]>; 7]) -> Option<Want> {
    let limited: Vec<(String, Want)> = joints
        .iter()
        .enumerate()
        .filter_map(|(index, limits)| {
            let [min, max] = (*limits)?;
            let pair = Want::List(vec![Want::Number(min), Want::Number(max)]);
            Some((format!("j{}", index + 1), pair))
        })
        .collect();
    (!limited.is_empty()).then_some(Want::Map(limited))
}

fn singularity(singularity: &Singularity) -> Want {
    Want::Map(vec![
        ("slow".into(), Want::Number(singularity.slow)),
        ("stop".into(), Want::Number(singularity.stop)),
    ])
}

/// Sets the keys of the fence table `table` (`standard`: it has a `[header]`).
fn merge_fence(table: &mut dyn TableLike, standard: bool, fence: &Fence) {
    match &fence.inside {
        Some(inside) => put(table, "inside", &aabb(inside)),
        None => {
            table.remove("inside");
        }
    }
    put(table, "tool_radius", &Want::Number(fence.tool_radius));
    put(table, "slow_zone", &Want::Number(fence.slow_zone));
    match joints(&fence.joints) {
        Some(joints) => put(table, "joints", &joints),
        None => {
            table.remove("joints");
        }
    }
    if fence.singularity != Singularity::default() || table.contains_key("singularity") {
        put(table, "singularity", &singularity(&fence.singularity));
    }
    if fence.keep_out.is_empty() {
        table.remove("keep_out");
    } else {
        merge_zones(table, standard, &fence.keep_out);
    }
}

/// Puts `want` at `key`: into what is there, keeping its formatting, or as a new inline value.
fn put(table: &mut dyn TableLike, key: &str, want: &Want) {
    match table.get_mut(key) {
        Some(item) => merge_item(item, want),
        None => {
            table.insert(key, Item::Value(value(want)));
        }
    }
}

fn merge_item(item: &mut Item, want: &Want) {
    match (item, want) {
        (Item::Value(old), _) => merge_value(old, want),
        // `[arms.NAME.fence.inside]` written as a table of its own stays one.
        (Item::Table(table), Want::Map(keys)) => merge_map(table, keys),
        (item, _) => *item = Item::Value(value(want)),
    }
}

/// `old` made `want`: tables key by key, arrays of the same length item by item, and a value
/// that differs replaced, keeping the spaces and comment about it.
fn merge_value(old: &mut Value, want: &Want) {
    match (old, want) {
        (Value::InlineTable(table), Want::Map(keys)) => {
            edit_inline(table, |table| merge_map(table, keys));
        }
        (Value::Array(items), Want::List(wants)) if items.len() == wants.len() => {
            for (item, want) in items.iter_mut().zip(wants) {
                merge_value(item, want);
            }
        }
        (old, want) => {
            if !same(old, want) {
                let decor = old.decor().clone();
                *old = value(want);
                *old.decor_mut() = decor;
            }
        }
    }
}

/// Edits the inline table `table`; when its last key changes, the spaces before its `}` (the last
/// value's) go to the new last value: `{ j2 = [-120, 120] }`, not `{ j2 = [-120, 120]}`.
fn edit_inline<R>(table: &mut InlineTable, edit: impl FnOnce(&mut InlineTable) -> R) -> R {
    let last = |table: &InlineTable| {
        table
            .iter()
            .last()
            .map(|(key, value)| (key.to_string(), value.decor().suffix().cloned()))
    };
    let before = last(table);
    let result = edit(table);
    let (Some((old_key, Some(end))), Some((new_key, _))) = (before, last(table)) else {
        return result;
    };
    if new_key == old_key {
        return result;
    }
    if let Some(old) = table.get_mut(&old_key)
        && old.decor().suffix() == Some(&end)
    {
        old.decor_mut().set_suffix("");
    }
    if let Some(new) = table.get_mut(&new_key) {
        new.decor_mut().set_suffix(end);
    }
    result
}

/// The keys of `keys` set in `table`, and no other.
fn merge_map(table: &mut dyn TableLike, keys: &[(String, Want)]) {
    for (key, want) in keys {
        put(table, key, want);
    }
    let gone: Vec<String> = table
        .iter()
        .map(|(key, _)| key.to_string())
        .filter(|key| !keys.iter().any(|(wanted, _)| wanted == key))
        .collect();
    for key in gone {
        table.remove(&key);
    }
}

/// Whether the file's `old` already reads as `want`.
fn same(old: &Value, want: &Want) -> bool {
    match (old, want) {
        (Value::Integer(old), Want::Number(want)) => *old.value() as f64 == *want,
        (Value::Float(old), Want::Number(want)) => *old.value() == *want,
        (Value::String(old), Want::Text(want)) => old.value() == want,
        (Value::Boolean(old), Want::Switch(want)) => old.value() == want,
        _ => false,
    }
}

/// `want` as a new value, in toml_edit's default formatting.
fn value(want: &Want) -> Value {
    match want {
        Want::Number(number) => self::number(*number),
        Want::Text(text) => Value::from(text.as_str()),
        Want::Switch(on) => Value::from(*on),
        Want::List(items) => Value::Array(items.iter().map(value).collect::<Array>()),
        Want::Map(keys) => {
            let mut table = InlineTable::new();
            for (key, want) in keys {
                table.insert(key, value(want));
            }
            Value::InlineTable(table)
        }
    }
}

/// A number as written anew: to a tenth, an integer when whole (`-600`, not `-600.0`).
fn number(number: f64) -> Value {
    let number = tenth(number);
    // Whole and within the integers a float holds exactly.
    if number.fract() == 0.0 && number.abs() < 9.0e15 {
        Value::from(number as i64)
    } else {
        Value::from(number)
    }
}

/// A zone's keys set in `table`: `name`, `min`, `max`, and `enabled` when off or already written.
fn merge_zone(table: &mut dyn TableLike, zone: &KeepOut) {
    put(table, "name", &Want::Text(zone.name.clone()));
    put(table, "min", &corner(zone.zone.min));
    put(table, "max", &corner(zone.zone.max));
    if !zone.enabled || table.contains_key("enabled") {
        put(table, "enabled", &Want::Switch(zone.enabled));
    }
}

/// The name a zone's table gives.
fn zone_name(table: &dyn TableLike) -> Option<&str> {
    table.get("name").and_then(Item::as_str)
}

/// Sets the fence's `keep_out` zones, matched by name, in the form the file has them.
fn merge_zones(fence: &mut dyn TableLike, standard: bool, zones: &[KeepOut]) {
    match fence.get_mut("keep_out") {
        Some(Item::ArrayOfTables(tables)) => {
            let old = std::mem::take(tables);
            *tables = merge_zone_tables(old, zones);
        }
        Some(Item::Value(Value::Array(values))) => merge_zone_values(values, zones),
        Some(other) => *other = new_zones(standard, zones),
        None => {
            fence.insert("keep_out", new_zones(standard, zones));
        }
    }
}

/// `[[...keep_out]]` tables: a zone kept keeps its table (comments and all); the kept ones take,
/// in the fence's order, the places the kept tables had; a new one follows the one before it.
fn merge_zone_tables(old: ArrayOfTables, zones: &[KeepOut]) -> ArrayOfTables {
    let mut old: Vec<Option<Table>> = old.into_iter().map(Some).collect();
    let mut places = Vec::new();
    let mut kept = Vec::new();
    let mut tables = Vec::with_capacity(zones.len());
    for zone in zones {
        let found = old
            .iter_mut()
            .find(|t| t.as_ref().and_then(|t| zone_name(t)) == Some(zone.name.as_str()))
            .and_then(Option::take);
        let mut table = match found {
            Some(table) => {
                places.extend(table.position());
                kept.push(tables.len());
                table
            }
            None => Table::new(),
        };
        merge_zone(&mut table, zone);
        tables.push(table);
    }
    places.sort_unstable();
    for (index, place) in kept.into_iter().zip(places) {
        if let Some(table) = tables.get_mut(index) {
            table.set_position(Some(place));
        }
    }
    let mut out = ArrayOfTables::new();
    for table in tables {
        out.push(table);
    }
    out
}

/// `keep_out = [{ name = ... }, ...]`: a zone kept keeps its inline table and the spaces about
/// it; a new one is spaced as the last zone the file had (on a line of its own if that was); the
/// spaces before the `]` stay at the end.
fn merge_zone_values(values: &mut Array, zones: &[KeepOut]) {
    let mut old: Vec<Option<(InlineTable, Decor)>> = values
        .iter()
        .map(|v| Some((v.as_inline_table()?.clone(), v.decor().clone())))
        .collect();
    let end = values
        .iter()
        .last()
        .and_then(|v| v.decor().suffix().cloned());
    // The last zone's spaces before it, if they part it from the one before or start a line.
    let spacing = values
        .iter()
        .last()
        .and_then(|v| v.decor().prefix().cloned())
        .filter(|prefix| values.len() > 1 || prefix.as_str().is_some_and(|p| p.contains('\n')));
    values.clear();
    for zone in zones {
        let found = old
            .iter_mut()
            .find(|t| t.as_ref().and_then(|(t, _)| zone_name(t)) == Some(zone.name.as_str()))
            .and_then(Option::take);
        let mut value = match found {
            Some((mut table, decor)) => {
                edit_inline(&mut table, |table| merge_zone(table, zone));
                let mut value = Value::InlineTable(table);
                *value.decor_mut() = decor;
                value
            }
            None => {
                let mut table = InlineTable::new();
                merge_zone(&mut table, zone);
                let mut value = Value::InlineTable(table);
                if let Some(prefix) = &spacing {
                    value.decor_mut().set_prefix(prefix.clone());
                    value.decor_mut().set_suffix("");
                }
                value
            }
        };
        if let Some(end) = &end {
            let suffix = value.decor().suffix().cloned();
            if suffix.as_ref() == Some(end) {
                value.decor_mut().set_suffix("");
            }
        }
        values.push_formatted(value);
    }
    if let (Some(end), Some(last)) = (end, values.iter_mut().last()) {
        last.decor_mut().set_suffix(end);
    }
}

/// New zones: `[[...keep_out]]` tables under a `[header]`, else an array of inline tables.
fn new_zones(standard: bool, zones: &[KeepOut]) -> Item {
    if standard {
        let mut tables = ArrayOfTables::new();
        for zone in zones {
            let mut table = Table::new();
            merge_zone(&mut table, zone);
            tables.push(table);
        }
        Item::ArrayOfTables(tables)
    } else {
        let mut values = Array::new();
        for zone in zones {
            let mut table = InlineTable::new();
            merge_zone(&mut table, zone);
            values.push(Value::InlineTable(table));
        }
        Item::Value(Value::Array(values))
    }
}

/// A profile setting as its option's text gives it: a number if it reads as one, else a string.
fn setting(text: &str) -> Value {
    match text.parse::<f64>() {
        Ok(n) if n.is_finite() => number(n),
        _ => Value::from(text),
    }
}
