//! The yes/no questions the console asks before it moves the arm, deletes, replaces or quits.

use super::{Form, FormResult, TourQuestion};
use crate::kortex::Stored;

/// What a yes/no question is about.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Confirm {
    Home,
    GoTo(String),
    Delete(String),
    /// The operator lost this name: re-save it from the remembered coordinates, then go there.
    Resave(String),
    /// A submitted form would replace the position of that name; `form` comes back on no.
    Overwrite {
        result: FormResult,
        form: Box<Form>,
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
    pub fn question(&self) -> String {
        match self {
            Confirm::Home => "Move the arm to its home pose?".into(),
            Confirm::GoTo(name) => format!("Move the arm to '{name}'?"),
            Confirm::Delete(name) => format!("Delete position '{name}'?"),
            Confirm::Resave(name) => format!(
                "'{name}' is unknown to the operator: re-save it from the remembered coordinates \
                 and move the arm there?"
            ),
            Confirm::Overwrite { result, .. } => format!("overwrite '{}'?", result.name()),
            Confirm::QuitUnsaved { count } => format!(
                "{count} changed position(s) could not be saved: quit anyway? The book is \
                 written once more as the console quits"
            ),
            Confirm::Tour(tour) => tour.question(),
            Confirm::Stored(stored) => format!("Run {stored} on the arm?"),
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
            _ => "y or enter: yes    any other key: no",
        }
    }
}
