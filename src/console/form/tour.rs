//! The tour forms. Making one: a name and comma-separated positions (`bench, pick, place`),
//! prefilled from the list, each passing the name rule (the app checks they exist). Playing one:
//! the name, prefilled with the last tour.

use super::confirm::QuestionText;
use super::{Field, Form, FormKind};
use crate::console::positions::{LEG_SEPARATOR, Tour};
use crate::talos::PositionName;

/// The question before a tour's first move.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TourQuestion {
    pub tour: Tour,
    pub one_leg: bool,
}

impl TourQuestion {
    /// `Play tour 'rounds' straight through, 3 legs: bench → pick → place?`
    pub fn question(&self) -> String {
        self.text().whole()
    }

    /// The question, its legs apart so the dialog can shorten them.
    pub fn text(&self) -> QuestionText<'_> {
        let mode = if self.one_leg {
            "one leg at a time"
        } else {
            "straight through"
        };
        let legs = self.tour.positions.len();
        QuestionText {
            before: format!(
                "Play tour '{}' {mode}, {legs} leg{}: ",
                self.tour.name,
                if legs == 1 { "" } else { "s" },
            ),
            list: &self.tour.positions,
            separator: LEG_SEPARATOR,
            after: "?".into(),
        }
    }
}

/// The positions field's label: it takes a longer paste than a number field.
pub(super) const LEGS_LABEL: &str = "positions";
/// The most a paste puts in the positions field.
pub(super) const LEGS_PASTE_LIMIT: usize = 4096;

pub(super) fn make_fields(name: &str, legs: &str) -> Vec<Field> {
    vec![
        Field::name("tour name", name),
        Field::text(LEGS_LABEL, legs),
    ]
}

impl Form {
    /// The form making a tour named `name` (empty for a new one) of `positions`, in order.
    pub fn make_tour(name: &str, positions: &[&str]) -> Form {
        Form {
            fields: make_fields(name, &positions.join(", ")),
            note: Some("positions in order, separated by commas"),
            ..Form::new(FormKind::MakeTour, name)
        }
    }

    /// The form asking which tour to play, prefilled with `name`.
    pub fn play_tour(name: &str, one_leg: bool) -> Form {
        Form::new(FormKind::PlayTour { one_leg }, name)
    }

    /// The positions field as names, each by the name rule, at least one.
    pub(super) fn tour_legs(&self) -> Result<Vec<String>, (usize, String)> {
        let text = self.value(1);
        let mut legs = Vec::new();
        for (i, part) in text.split(',').map(str::trim).enumerate() {
            if part.is_empty() && text.is_empty() {
                break;
            }
            let name =
                PositionName::new(part).map_err(|e| (1, format!("position {} {e}", i + 1)))?;
            legs.push(name.as_str().to_string());
        }
        if legs.is_empty() {
            return Err((1, "a tour needs at least one position".into()));
        }
        Ok(legs)
    }
}

#[cfg(test)]
mod tests {
    use super::super::FormResult;
    use super::*;

    #[test]
    fn the_make_form_is_prefilled_in_order_and_gives_the_names() {
        let mut form = Form::make_tour("", &["bench", "pick", "place"]);
        assert_eq!(form.fields[1].value, "bench, pick, place");
        assert!(form.submit().is_none(), "no tour name");
        assert!(
            form.error
                .as_deref()
                .unwrap_or("")
                .contains("name is empty")
        );
        form.focus = 0;
        "rounds".chars().for_each(|c| form.type_char(c));
        assert_eq!(
            form.submit(),
            Some(FormResult::MakeTour {
                name: "rounds".into(),
                positions: vec!["bench".into(), "pick".into(), "place".into()],
            })
        );
    }

    #[test]
    fn an_empty_list_or_an_empty_name_in_it_is_refused_on_the_positions_field() {
        let mut form = Form::make_tour("t", &[]);
        assert_eq!(form.submit(), None);
        assert_eq!(form.focus, 1);
        assert!(form.error.as_deref().unwrap_or("").contains("at least one"));
        let mut form = Form::make_tour("t", &["bench", "", "pick"]);
        assert_eq!(form.submit(), None);
        let said = form.error.clone().unwrap_or_default();
        assert!(
            said.contains("position 2") && said.contains("empty"),
            "{said}"
        );
    }

    #[test]
    fn the_play_form_says_its_mode() {
        let mut form = Form::play_tour("rounds", true);
        assert_eq!(form.title(), "Play a tour one leg at a time");
        assert_eq!(
            form.submit(),
            Some(FormResult::PlayTour {
                name: "rounds".into(),
                one_leg: true
            })
        );
    }
}
