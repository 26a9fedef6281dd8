//! The three-way merge: each side's changes survive, nothing is lost when both change a name.

use super::*;

fn at(x: i32) -> BookEntry {
    BookEntry {
        cartesian: Some([x, 0, 0]),
        ..BookEntry::default()
    }
}

fn book(entries: &[(&str, i32)], tours: &[(&str, &[&str])]) -> PositionBook {
    let mut book = PositionBook::new();
    for (name, x) in entries {
        *book.get_or_insert(name) = at(*x);
    }
    for (name, legs) in tours {
        book.set_tour(Tour {
            name: name.to_string(),
            positions: legs.iter().map(|l| l.to_string()).collect(),
        });
    }
    book
}

fn xs(book: &PositionBook) -> Vec<(String, i32)> {
    book.entries()
        .map(|(n, e)| (n.to_string(), e.cartesian.map_or(-1, |c| c[0])))
        .collect()
}

/// No position saved or edited here but by value.
fn none() -> BTreeSet<String> {
    BTreeSet::new()
}

fn touched(names: &[&str]) -> BTreeSet<String> {
    names.iter().map(|n| n.to_string()).collect()
}

fn pairs(entries: &[(&str, i32)]) -> Vec<(String, i32)> {
    entries.iter().map(|(n, x)| (n.to_string(), *x)).collect()
}

#[test]
fn a_position_each_side_added_is_in_the_merge() {
    // Console 1 saved X1 since console 2 read the file; console 2 saves X3.
    let known = book(&[("home", 0)], &[]);
    let theirs = book(&[("home", 0), ("x1", 1)], &[]);
    let ours = book(&[("home", 0), ("x3", 3)], &[]);
    let merged = merge(&known, &ours, &theirs, &none());
    assert_eq!(
        xs(&merged.book),
        pairs(&[("home", 0), ("x1", 1), ("x3", 3)])
    );
    assert_eq!(merged.taken, 1);
    assert!(merged.conflicts.is_empty());
}

#[test]
fn a_deletion_on_either_side_is_kept_and_a_change_on_either_side_is_taken() {
    let known = book(&[("a", 1), ("b", 2), ("c", 3), ("d", 4)], &[]);
    // We deleted a and changed c; they deleted b and changed d.
    let ours = book(&[("b", 2), ("c", 30), ("d", 4)], &[]);
    let theirs = book(&[("a", 1), ("c", 3), ("d", 40)], &[]);
    let merged = merge(&known, &ours, &theirs, &none());
    assert_eq!(xs(&merged.book), pairs(&[("c", 30), ("d", 40)]));
    assert_eq!(merged.taken, 2, "b's deletion and d's change");
    assert!(merged.conflicts.is_empty());
}

#[test]
fn a_name_both_changed_keeps_both_and_says_so() {
    let known = book(&[("pick", 1), ("pick~2", 9)], &[]);
    let ours = book(&[("pick", 2), ("pick~2", 9)], &[]);
    let theirs = book(&[("pick", 3), ("pick~2", 9)], &[]);
    let merged = merge(&known, &ours, &theirs, &none());
    assert_eq!(
        xs(&merged.book),
        pairs(&[("pick", 3), ("pick~2", 9), ("pick~3", 2)]),
        "theirs keeps the name, ours is beside it under a free name"
    );
    assert_eq!(
        merged.conflicts,
        [Conflict {
            kind: "position",
            name: "pick".into(),
            outcome: Kept::Both {
                copy: "pick~3".into()
            },
        }]
    );
    let said = merged.conflicts[0].describe();
    assert!(
        said.contains("'pick'") && said.contains("'pick~3'"),
        "{said}"
    );
    // Both added the same name, differently: the same.
    let merged = merge(
        &book(&[], &[]),
        &book(&[("new", 1)], &[]),
        &book(&[("new", 2)], &[]),
        &none(),
    );
    assert_eq!(xs(&merged.book), pairs(&[("new", 2), ("new~2", 1)]));
}

#[test]
fn a_deletion_against_a_change_keeps_the_changed_entry() {
    let known = book(&[("a", 1), ("b", 2)], &[]);
    let ours = book(&[("b", 20)], &[]);
    let theirs = book(&[("a", 10)], &[]);
    let merged = merge(&known, &ours, &theirs, &none());
    assert_eq!(xs(&merged.book), pairs(&[("a", 10), ("b", 20)]));
    let outcomes: Vec<(&str, &Kept)> = merged
        .conflicts
        .iter()
        .map(|c| (c.name.as_str(), &c.outcome))
        .collect();
    assert_eq!(
        outcomes,
        [("a", &Kept::TheirsNotDeleted), ("b", &Kept::OursNotDeleted)]
    );
}

#[test]
fn the_same_change_on_both_sides_and_marks_not_saved_are_no_conflict() {
    let known = book(&[("a", 1)], &[]);
    let mut ours = book(&[("a", 2)], &[]);
    if let Some(a) = ours.get_mut("a") {
        a.unsaved = true;
        a.unknown_to_operator = true;
    }
    let theirs = book(&[("a", 2)], &[]);
    let merged = merge(&known, &ours, &theirs, &none());
    assert!(merged.conflicts.is_empty());
    assert_eq!(merged.taken, 0);
    assert!(
        merged.book.get("a").is_some_and(|a| a.unknown_to_operator),
        "ours is kept with what the panel marks"
    );
}

#[test]
fn tours_merge_by_name_in_the_files_order_then_ours() {
    let known = book(&[], &[("rounds", &["a"])]);
    // A tour added by hand to the file while the console ran; the console made another.
    let theirs = book(&[], &[("rounds", &["a"]), ("by hand", &["a", "b"])]);
    let ours = book(&[], &[("rounds", &["a"]), ("mine", &["b"])]);
    let merged = merge(&known, &ours, &theirs, &none());
    let names: Vec<&str> = merged
        .book
        .tours()
        .iter()
        .map(|t| t.name.as_str())
        .collect();
    assert_eq!(names, ["rounds", "by hand", "mine"]);
    assert_eq!(merged.taken, 1);
    // Both changed one tour: both kept.
    let ours = book(&[], &[("rounds", &["b"])]);
    let theirs = book(&[], &[("rounds", &["c"])]);
    let merged = merge(&known, &ours, &theirs, &none());
    let tours: Vec<(&str, String)> = merged
        .book
        .tours()
        .iter()
        .map(|t| (t.name.as_str(), t.legs_text()))
        .collect();
    assert_eq!(tours, [("rounds", "c".into()), ("rounds~2", "b".into())]);
    assert_eq!(merged.conflicts.len(), 1);
    // We deleted it: deleted, as they did not change it.
    let merged = merge(&known, &book(&[], &[]), &known, &none());
    assert!(merged.book.tours().is_empty());
}

#[test]
fn incorporating_a_write_keeps_what_changed_here_since() {
    let handed = book(&[("a", 1)], &[]);
    // The write took b from the other console; meanwhile a changed here and c was added.
    let written = book(&[("a", 1), ("b", 2)], &[]);
    let now = book(&[("a", 10), ("c", 3)], &[]);
    let book_now = incorporate(&handed, &now, &written);
    assert_eq!(xs(&book_now), pairs(&[("a", 10), ("b", 2), ("c", 3)]));
    // A name changed here since and by the write: this console's change stays, no copy.
    let written = book(&[("a", 5)], &[]);
    let book_now = incorporate(&handed, &now, &written);
    assert_eq!(xs(&book_now), pairs(&[("a", 10), ("c", 3)]));
}

#[test]
fn a_name_saved_here_at_its_old_value_is_a_change_here() {
    // X3 was P (1) in the file as read; another program made it Q (2); the technician saved
    // X3 at P again (and overwrote): both changed it, both are kept and it is asked.
    let known = book(&[("x3", 1)], &[]);
    let ours = book(&[("x3", 1)], &[]);
    let theirs = book(&[("x3", 2)], &[]);
    let merged = merge(&known, &ours, &theirs, &touched(&["x3"]));
    assert_eq!(xs(&merged.book), pairs(&[("x3", 2), ("x3~2", 1)]));
    assert_eq!(merged.taken, 0, "nothing taken silently");
    assert_eq!(
        merged.conflicts,
        [Conflict {
            kind: "position",
            name: "x3".into(),
            outcome: Kept::Both {
                copy: "x3~2".into()
            },
        }]
    );
    // Not saved here: theirs is taken, as before.
    let merged = merge(&known, &ours, &theirs, &none());
    assert_eq!(xs(&merged.book), pairs(&[("x3", 2)]));
    assert_eq!(merged.taken, 1);
    // Saved here and deleted there: kept, and said.
    let merged = merge(&known, &ours, &book(&[], &[]), &touched(&["x3"]));
    assert_eq!(xs(&merged.book), pairs(&[("x3", 1)]));
    assert_eq!(merged.conflicts[0].outcome, Kept::OursNotDeleted);
    // Saved here, unchanged there: ours, no conflict; saved the same on both: no conflict.
    let merged = merge(&known, &book(&[("x3", 5)], &[]), &known, &touched(&["x3"]));
    assert_eq!(xs(&merged.book), pairs(&[("x3", 5)]));
    assert!(merged.conflicts.is_empty());
    let merged = merge(&known, &theirs, &theirs, &touched(&["x3"]));
    assert_eq!(xs(&merged.book), pairs(&[("x3", 2)]));
    assert!(merged.conflicts.is_empty());
}

#[test]
fn our_position_moved_beside_its_name_by_another_writer_is_said() {
    // We wrote pick (1); the other console kept ours as pick~2 and then gave its own (2) the
    // name (its technician's "yes" to the conflict's question).
    let known = book(&[("pick", 1)], &[]);
    let ours = book(&[("pick", 1), ("other", 7)], &[]);
    let theirs = book(&[("pick", 2), ("pick~2", 1)], &[]);
    let merged = merge(&known, &ours, &theirs, &touched(&["other"]));
    assert_eq!(
        xs(&merged.book),
        pairs(&[("other", 7), ("pick", 2), ("pick~2", 1)])
    );
    assert_eq!(
        merged.moved,
        [Moved {
            name: "pick".into(),
            to: "pick~2".into()
        }]
    );
    assert!(
        merged.moved[0]
            .describe()
            .contains("'pick' was kept as 'pick~2'")
    );
    // A plain change of pick there (no copy of ours) is no move; nor is a copy of another value.
    let theirs = book(&[("pick", 2), ("pick~2", 3)], &[]);
    assert!(merge(&known, &ours, &theirs, &none()).moved.is_empty());
    let theirs = book(&[("pick", 2), ("pickle", 1)], &[]);
    assert!(merge(&known, &ours, &theirs, &none()).moved.is_empty());
}
