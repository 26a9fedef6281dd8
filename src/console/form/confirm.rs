//! The yes/no questions asked before moving, deleting, replacing or quitting. A question that lists
//! things gives its list apart ([`QuestionText`]) so the dialog can count what does not fit and its
//! answers always show.

use super::{Form, FormResult, TourQuestion};
use crate::kortex::Stored;

/// A question's words before and after a list of things, each shown whole or not at all.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct QuestionText<'a> {
    pub before: String,
    pub list: &'a [String],
    /// Between two things of the list.
    pub separator: &'static str,
    pub after: String,
}

impl QuestionText<'_> {
    /// A question without a list.
    pub fn plain(text: String) -> QuestionText<'static> {
        QuestionText {
            before: text,
            list: &[],
            separator: "",
            after: String::new(),
        }
    }

    /// The question with its first `shown` things, the rest counted.
    pub fn with_first(&self, shown: usize) -> String {
        let shown = shown.min(self.list.len());
        let mut text = self.before.clone();
        text.push_str(&self.list[..shown].join(self.separator));
        let more = self.list.len() - shown;
        if more > 0 {
            if shown > 0 {
                text.push(' ');
            }
            text.push_str(&format!("… and {more} more"));
        }
        text.push_str(&self.after);
        text
    }

    /// The whole question, every thing of its list in it.
    pub fn whole(&self) -> String {
        self.with_first(self.list.len())
    }
}

/// What a yes/no question is about.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Confirm {
    Home,
    GoTo(String),
    /// Delete a position; `tours` are those that visit it (they cannot be played without it).
    Delete {
        name: String,
        tours: Vec<String>,
    },
    /// The operator lost this name: re-save it from the remembered coordinates, then go there.
    Resave(String),
    /// A submitted form would replace the position of that name; `form` comes back on no.
    Overwrite {
        result: FormResult,
        form: Box<Form>,
    },
    /// A position changed here and elsewhere, both kept (theirs `name`, ours `copy`); yes swaps.
    BothChanged {
        name: String,
        copy: String,
    },
    /// Quitting while `count` changed positions could not be written.
    QuitUnsaved {
        count: usize,
    },
    /// Play a tour: it names the tour and its legs.
    Tour(TourQuestion),
    /// Running a stored action or sequence by id.
    Stored(Stored),
}

impl Confirm {
    /// The whole question, as one line of text (its list whole).
    pub fn question(&self) -> String {
        self.text().whole()
    }

    /// The question, its list apart: what the dialog fits to the screen.
    pub fn text(&self) -> QuestionText<'_> {
        let plain = QuestionText::plain;
        match self {
            Confirm::Home => plain("Move the arm to its home pose?".into()),
            Confirm::GoTo(name) => plain(format!("Move the arm to '{name}'?")),
            Confirm::Delete { name, tours } if tours.is_empty() => {
                plain(format!("Delete position '{name}'?"))
            }
            // tour_list names at most five tours and counts the rest.
            Confirm::Delete { name, tours } => plain(format!(
                "Delete position '{name}'? {} visit{} it and cannot be played without it (undo \
                 restores it)",
                capitalised(&tour_list(tours)),
                if tours.len() == 1 { "s" } else { "" }
            )),
            Confirm::Resave(name) => plain(format!(
                "'{name}' is unknown to the operator: re-save it from the remembered coordinates \
                 and move the arm there?"
            )),
            Confirm::Overwrite { result, .. } => plain(format!("overwrite '{}'?", result.name())),
            Confirm::BothChanged { name, copy } => plain(format!(
                "'{name}' was changed here and by another program: both are kept, theirs as \
                 '{name}', this console's as '{copy}'. Give this console's the name '{name}' \
                 (theirs becomes '{copy}')?"
            )),
            Confirm::QuitUnsaved { count } => plain(format!(
                "{count} changed position(s) could not be saved: quit anyway? The book is \
                 written once more as the console quits"
            )),
            Confirm::Tour(tour) => tour.text(),
            Confirm::Stored(stored) => plain(format!("Run {stored} on the arm?")),
        }
    }

    /// The answers, as the dialog shows them.
    pub fn answers(&self) -> &'static str {
        match self {
            // Enter just submitted the form: only y replaces a position.
            Confirm::Overwrite { .. } => {
                "y: overwrite    n, esc or any other key: back to the form"
            }
            Confirm::QuitUnsaved { .. } => "y: quit    any other key: stay",
            Confirm::BothChanged { .. } => "y: swap them    any other key: keep both as they are",
            _ => "y or enter: yes    any other key: no",
        }
    }
}

/// "tour 'a'", "tours 'a', 'b' and 'c'", "tours 'a', 'b', 'c', 'd', 'e' and 3 more".
pub fn tour_list(tours: &[String]) -> String {
    const NAMED: usize = 5;
    let quoted: Vec<String> = tours.iter().take(NAMED).map(|t| format!("'{t}'")).collect();
    let more = tours.len().saturating_sub(NAMED);
    let (head, last) = match (quoted.split_last(), more) {
        (None, _) => return "no tour".into(),
        (Some((only, [])), 0) => return format!("tour {only}"),
        (Some(_), more) if more > 0 => (quoted.join(", "), format!("{more} more")),
        (Some((last, rest)), _) => (rest.join(", "), last.clone()),
    };
    format!("tours {head} and {last}")
}

fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    chars
        .next()
        .map(|first| first.to_uppercase().chain(chars).collect())
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: usize) -> Vec<String> {
        (0..n).map(|i| format!("t{i}")).collect()
    }

    #[test]
    fn a_list_of_tours_names_five_at_most() {
        assert_eq!(tour_list(&names(1)), "tour 't0'");
        assert_eq!(tour_list(&names(2)), "tours 't0' and 't1'");
        assert_eq!(tour_list(&names(3)), "tours 't0', 't1' and 't2'");
        assert_eq!(
            tour_list(&names(8)),
            "tours 't0', 't1', 't2', 't3', 't4' and 3 more"
        );
    }
}
