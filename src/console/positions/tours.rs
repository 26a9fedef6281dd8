//! Tours: ordered lists of named positions, kept in the book's file.

use serde::{Deserialize, Serialize};

use super::PositionBook;
use crate::talos::PositionName;
use crate::text;

/// One tour: its name and the positions it visits, in order.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tour {
    pub name: String,
    pub positions: Vec<String>,
}

/// Between two legs of a tour, where its positions are listed.
pub const LEG_SEPARATOR: &str = " → ";

impl Tour {
    /// `bench → pick → place`.
    pub fn legs_text(&self) -> String {
        self.positions.join(LEG_SEPARATOR)
    }
}

impl PositionBook {
    /// The tours, in the order they were made.
    pub fn tours(&self) -> &[Tour] {
        &self.tours
    }

    pub fn tour(&self, name: &str) -> Option<&Tour> {
        self.tours.iter().find(|t| t.name == name)
    }

    /// Adds `tour` or replaces its namesake in place; returns whether one was replaced.
    pub fn set_tour(&mut self, tour: Tour) -> bool {
        let old = self.tours.iter().position(|t| t.name == tour.name);
        match old {
            Some(i) => self.tours[i] = tour,
            None => self.tours.push(tour),
        }
        old.is_some()
    }

    /// The first of `names` the book has no position for, with its place (0-based).
    pub fn first_missing<'a>(&self, names: &'a [String]) -> Option<(usize, &'a str)> {
        names
            .iter()
            .enumerate()
            .find(|(_, name)| self.get(name).is_none())
            .map(|(i, name)| (i, name.as_str()))
    }

    /// The names of the tours that visit `position`, in the book's order.
    pub fn tours_using(&self, position: &str) -> Vec<String> {
        self.tours
            .iter()
            .filter(|t| t.positions.iter().any(|p| p == position))
            .map(|t| t.name.clone())
            .collect()
    }

    /// `from` renamed `to` in every tour; returns the tours changed.
    pub fn rename_in_tours(&mut self, from: &str, to: &str) -> Vec<String> {
        let mut changed = Vec::new();
        for tour in &mut self.tours {
            let legs = tour.positions.iter_mut().filter(|p| *p == from);
            if legs.map(|leg| *leg = to.to_string()).count() > 0 {
                changed.push(tour.name.clone());
            }
        }
        changed
    }

    /// Adds `other`'s tours, replacing those of the same name.
    pub(super) fn merge_tours(&mut self, other: &PositionBook) {
        for tour in other.tours.iter() {
            self.set_tour(tour.clone());
        }
    }

    /// After loading: a tour with a bad name is dropped with a note.
    pub(super) fn repair_tours(&mut self) {
        let breaks = |name: &str| PositionName::validate(name.as_bytes()).is_err();
        let mut kept: Vec<Tour> = Vec::new();
        for tour in std::mem::take(&mut self.tours) {
            if breaks(&tour.name) || tour.positions.iter().any(|p| breaks(p)) {
                self.load_notes.push(format!(
                    "tour '{}' dropped: a name in it breaks the name rule",
                    text::logged(&tour.name)
                ));
                continue;
            }
            kept.retain(|t| t.name != tour.name);
            kept.push(tour);
        }
        self.tours = kept;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tour(name: &str, positions: &[&str]) -> Tour {
        Tour {
            name: name.into(),
            positions: positions.iter().map(|p| p.to_string()).collect(),
        }
    }

    #[test]
    fn a_tour_of_a_name_replaces_it_in_place_and_missing_positions_are_named() {
        let mut book = PositionBook::new();
        book.get_or_insert("bench");
        assert!(!book.set_tour(tour("a", &["bench"])));
        assert!(!book.set_tour(tour("b", &["bench", "gone"])));
        assert!(book.set_tour(tour("a", &["bench", "bench"])));
        let names: Vec<&str> = book.tours().iter().map(|t| t.name.as_str()).collect();
        assert_eq!(names, ["a", "b"]);
        assert_eq!(book.tour("a").map(|t| t.positions.len()), Some(2));
        let b = book.tour("b").cloned().expect("b");
        assert_eq!(book.first_missing(&b.positions), Some((1, "gone")));
        assert_eq!(b.legs_text(), "bench → gone");
    }

    #[test]
    fn a_rename_carries_into_every_tour_and_the_tours_using_a_name_are_found() {
        let mut book = PositionBook::new();
        book.set_tour(tour("a", &["pick", "bench", "pick"]));
        book.set_tour(tour("b", &["bench"]));
        book.set_tour(tour("c", &["pick"]));
        assert_eq!(book.tours_using("pick"), ["a", "c"]);
        assert_eq!(book.rename_in_tours("pick", "grip"), ["a", "c"]);
        assert_eq!(
            book.tour("a").map(Tour::legs_text).as_deref(),
            Some("grip → bench → grip")
        );
        assert!(book.tours_using("pick").is_empty());
        assert!(book.rename_in_tours("nothing", "x").is_empty());
    }

    #[test]
    fn tours_round_trip_through_the_file_and_an_old_book_without_them_loads() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("book.json");
        let mut book = PositionBook::new();
        book.get_or_insert("bench").cartesian = Some([4000, 0, 3000]);
        book.set_tour(tour("rounds", &["bench", "gone"]));
        book.save(&path).expect("saved");
        let text = std::fs::read_to_string(&path).expect("read");
        assert!(text.contains("\"tours\""), "{text}");
        assert_eq!(PositionBook::load(&path).expect("loaded"), book);
        // Written before tours: no "tours" key at all.
        let old = r#"{"format": 1, "positions": {"bench": {"cartesian": [4000, 0, 3000]}}}"#;
        std::fs::write(&path, old).expect("write");
        let loaded = PositionBook::load(&path).expect("an old book loads");
        assert!(loaded.tours().is_empty());
        assert_eq!(
            loaded.get("bench").and_then(|e| e.cartesian),
            Some([4000, 0, 3000])
        );
        // And a book without tours writes no "tours" key.
        loaded.save(&path).expect("saved");
        let text = std::fs::read_to_string(&path).expect("read");
        assert!(!text.contains("tours"), "{text}");
    }

    #[test]
    fn a_tour_with_a_name_breaking_the_rule_is_dropped_with_a_note() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("book.json");
        let text = r#"{"format": 1, "positions": {}, "tours": [
            {"name": "ok", "positions": ["a"]},
            {"name": "bad", "positions": ["\u202e"]}]}"#;
        std::fs::write(&path, text).expect("write");
        let mut book = PositionBook::load(&path).expect("loaded");
        let names: Vec<&str> = book.tours().iter().map(|t| t.name.as_str()).collect();
        assert_eq!(names, ["ok"]);
        let notes = book.take_load_notes();
        assert_eq!(
            notes,
            ["tour 'bad' dropped: a name in it breaks the name rule"]
        );
    }
}
