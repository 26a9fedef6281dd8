//! Small forms and questions over the panels; input is checked here, the form kept on error.

use crate::kortex::Stored;
use crate::talos::name::{MAX_NAME_LEN, NameError};

/// Which form is open.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FormKind {
    /// Save the current pose: name, parent, anchor.
    Save,
    /// Define a position by elevation, azimuth (deg) and radius (mm).
    SetPolar,
    /// Define a position by x, y, z (mm).
    SetCartesian,
    /// Give a position another name.
    Rename,
    /// Make (or replace) a tour: its name and its positions in order (see `form/tour.rs`).
    MakeTour,
    /// Play a tour, straight through or one leg at a time.
    PlayTour { one_leg: bool },
    /// Start a stored action or sequence by id (`form/stored.rs`).
    Stored,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Field {
    pub label: &'static str,
    pub value: String,
    /// A yes/no field toggled with space instead of typed.
    pub toggle: bool,
    /// A position name: over [`MAX_NAME_LEN`] bytes it is refused as it is typed, not cut.
    pub name: bool,
}

impl Field {
    fn text(label: &'static str, value: &str) -> Field {
        Field {
            label,
            value: value.to_string(),
            toggle: false,
            name: false,
        }
    }

    fn name(label: &'static str, value: &str) -> Field {
        Field {
            name: true,
            ..Field::text(label, value)
        }
    }

    fn toggle(label: &'static str) -> Field {
        Field {
            toggle: true,
            ..Field::text(label, "no")
        }
    }

    /// Why the text cannot be a name whatever else is typed: it is too long.
    fn too_long(&self) -> Option<String> {
        let len = self.value.trim().len();
        (self.name && len > MAX_NAME_LEN)
            .then(|| format!("{} {}: delete some", self.label, NameError::TooLong(len)))
    }
}

/// The most a number field takes from a paste (a name field takes [`MAX_NAME_LEN`] bytes).
pub const NUMBER_PASTE_LIMIT: usize = 32;

/// What a paste into a form did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FormPaste {
    Inserted,
    /// The field was filled to its limit (bytes) and the rest dropped.
    Cut {
        limit: usize,
    },
    /// The focused field is a yes/no toggle: nothing was typed.
    Toggle,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Form {
    pub kind: FormKind,
    pub fields: Vec<Field>,
    pub focus: usize,
    /// Why the last submit was refused.
    pub error: Option<String>,
    /// The position being renamed (a rename form).
    pub original: Option<String>,
    /// What this form leaves out on this link and why, shown under its fields.
    pub note: Option<&'static str>,
}

/// Why the own-book save form has no anchor toggle; fits a dialog's 70 columns.
pub const NO_ANCHOR_NOTE: &str = "no anchor: this book is the console's own; anchors need Talos";

/// What a completed form asks for. Coordinates in the Talos ICD's tenths.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum FormResult {
    Save {
        name: String,
        anchor: bool,
        parent: Option<String>,
    },
    SetPolar {
        name: String,
        delta: i32,
        azimuth: i32,
        radius: i32,
    },
    SetCartesian {
        name: String,
        x: i32,
        y: i32,
        z: i32,
    },
    Rename {
        from: String,
        to: String,
    },
    MakeTour {
        name: String,
        positions: Vec<String>,
    },
    PlayTour {
        name: String,
        one_leg: bool,
    },
    /// A stored action or sequence to run (asked before it moves).
    Stored(Stored),
}

impl FormResult {
    /// The name the result saves under.
    pub fn name(&self) -> &str {
        match self {
            FormResult::Save { name, .. }
            | FormResult::SetPolar { name, .. }
            | FormResult::SetCartesian { name, .. } => name,
            FormResult::Rename { to, .. } => to,
            FormResult::MakeTour { name, .. } | FormResult::PlayTour { name, .. } => name,
            // Names no position: nothing is overwritten.
            FormResult::Stored(_) => "",
        }
    }
}

impl Form {
    /// A new form; `name` prefills the name field (the selected position).
    pub fn new(kind: FormKind, name: &str) -> Form {
        let fields = match kind {
            FormKind::Save => vec![
                Field::name("name", name),
                Field::name("parent", ""),
                Field::toggle("anchor"),
            ],
            FormKind::SetPolar => vec![
                Field::name("name", name),
                Field::text("elevation deg", ""),
                Field::text("azimuth deg", ""),
                Field::text("radius mm", ""),
            ],
            FormKind::SetCartesian => vec![
                Field::name("name", name),
                Field::text("x mm", ""),
                Field::text("y mm", ""),
                Field::text("z mm", ""),
            ],
            FormKind::Rename => vec![Field::name("new name", name)],
            FormKind::MakeTour => tour::make_fields(name, ""),
            FormKind::PlayTour { .. } => vec![Field::name("tour", name)],
            FormKind::Stored => return Form::stored(),
        };
        Form {
            kind,
            fields,
            focus: 0,
            error: None,
            original: None,
            note: None,
        }
    }

    /// The save form for the console's own book: no anchor toggle (it would do nothing there).
    pub fn save_to_own_book() -> Form {
        let mut form = Form::new(FormKind::Save, "");
        form.fields.retain(|field| field.label != "anchor");
        form.note = Some(NO_ANCHOR_NOTE);
        form
    }

    /// A form renaming `name`, prefilled with it.
    pub fn rename(name: &str) -> Form {
        Form {
            original: Some(name.to_string()),
            ..Form::new(FormKind::Rename, name)
        }
    }

    pub fn title(&self) -> &'static str {
        match self.kind {
            FormKind::Save => "Save current pose",
            FormKind::SetPolar => "Set polar position",
            FormKind::SetCartesian => "Set cartesian position",
            FormKind::Rename => "Rename position",
            FormKind::MakeTour => "Make a tour",
            FormKind::PlayTour { one_leg: false } => "Play a tour straight through",
            FormKind::PlayTour { one_leg: true } => "Play a tour one leg at a time",
            FormKind::Stored => "Run a stored action or sequence",
        }
    }

    pub fn next_field(&mut self) {
        self.focus = (self.focus + 1) % self.fields.len();
    }

    pub fn previous_field(&mut self) {
        self.focus = (self.focus + self.fields.len() - 1) % self.fields.len();
    }

    /// Typing into the focused field. Space toggles a yes/no field.
    pub fn type_char(&mut self, c: char) {
        let Some(field) = self.fields.get_mut(self.focus) else {
            return;
        };
        if field.toggle {
            if c == ' ' || c == 'y' || c == 'n' {
                let yes = match c {
                    'y' => true,
                    'n' => false,
                    _ => field.value != "yes",
                };
                field.value = if yes { "yes" } else { "no" }.into();
            }
        } else {
            // Nothing typed is cut: a name too long says so and stays editable.
            field.value.push(c);
        }
        self.error = field.too_long();
    }

    /// Pastes text into the focused field, controls removed, cut to the field's limit.
    pub fn paste(&mut self, text: &str) -> FormPaste {
        let Some(field) = self.fields.get_mut(self.focus) else {
            return FormPaste::Inserted;
        };
        if field.toggle {
            return FormPaste::Toggle;
        }
        let limit = if field.name {
            MAX_NAME_LEN
        } else if field.label == tour::LEGS_LABEL {
            tour::LEGS_PASTE_LIMIT
        } else {
            NUMBER_PASTE_LIMIT
        };
        let mut cut = false;
        for c in text.chars().filter(|c| !c.is_control()) {
            if field.value.len() + c.len_utf8() > limit {
                cut = true;
                break;
            }
            field.value.push(c);
        }
        self.error = field.too_long();
        match cut {
            true => FormPaste::Cut { limit },
            false => FormPaste::Inserted,
        }
    }

    pub fn backspace(&mut self) {
        if let Some(field) = self.fields.get_mut(self.focus)
            && !field.toggle
        {
            field.value.pop();
            self.error = field.too_long();
        }
    }

    /// Field `i`'s text, trimmed ("" past the last field).
    fn value(&self, i: usize) -> &str {
        self.fields.get(i).map_or("", |f| f.value.trim())
    }

    /// Validates every field. On error the form stays as typed, with the reason.
    pub fn submit(&mut self) -> Option<FormResult> {
        match self.parse() {
            Ok(result) => Some(result),
            Err((field, reason)) => {
                self.focus = field;
                self.error = Some(reason);
                None
            }
        }
    }
}

/// Answers a yes/no question about a position, the home pose or quitting.
mod confirm;
/// What a submitted form means, or the field that is wrong and why.
mod parse;
mod stored;
mod tour;

pub use confirm::{Confirm, QuestionText, tour_list};
pub use stored::STORED_NOTE;
pub use tour::TourQuestion;

#[cfg(test)]
mod tests {
    use super::*;

    fn typed(kind: FormKind, values: &[&str]) -> Form {
        let mut form = Form::new(kind, "");
        for (i, v) in values.iter().enumerate() {
            form.focus = i;
            for c in v.chars() {
                form.type_char(c);
            }
        }
        form
    }

    #[test]
    fn a_valid_save_form_gives_the_request() {
        let mut form = typed(FormKind::Save, &["pick 1", "table", " "]);
        assert_eq!(
            form.submit(),
            Some(FormResult::Save {
                name: "pick 1".into(),
                anchor: true,
                parent: Some("table".into())
            })
        );
    }

    #[test]
    fn the_save_form_for_the_consoles_own_book_has_no_anchor_toggle_and_says_why() {
        let mut form = Form::save_to_own_book();
        let labels: Vec<&str> = form.fields.iter().map(|f| f.label).collect();
        assert_eq!(labels, ["name", "parent"]);
        assert!(form.fields.iter().all(|f| !f.toggle));
        assert_eq!(form.note, Some(NO_ANCHOR_NOTE));
        assert_eq!(Form::new(FormKind::Save, "").note, None);
        for (i, v) in ["pick", "table"].iter().enumerate() {
            form.focus = i;
            for c in v.chars() {
                form.type_char(c);
            }
        }
        // Space in the last field is text, not a toggle.
        form.next_field();
        assert_eq!(form.focus, 0, "two fields: tab wraps to the name");
        assert_eq!(
            form.submit(),
            Some(FormResult::Save {
                name: "pick".into(),
                anchor: false,
                parent: Some("table".into())
            })
        );
    }

    #[test]
    fn invalid_names_are_refused_in_the_form_and_nothing_is_lost() {
        let mut form = typed(FormKind::Save, &["", "", ""]);
        assert_eq!(form.submit(), None);
        assert!(
            form.error
                .as_deref()
                .unwrap_or("")
                .contains("name is empty")
        );
        let mut form = typed(FormKind::Save, &["café", "", ""]);
        assert_eq!(form.submit(), None);
        assert!(
            form.error
                .as_deref()
                .unwrap_or("")
                .contains("printable ASCII")
        );
        assert_eq!(form.fields[0].value, "café", "the typed text stays");
        let mut form = typed(FormKind::Save, &["a", "", " "]);
        assert_eq!(form.submit(), None);
        assert_eq!(form.focus, 2);
    }

    #[test]
    fn a_name_over_255_bytes_is_refused_with_the_limit_and_nothing_is_cut() {
        let long = "n".repeat(300);
        let mut form = typed(FormKind::Save, &[&long, "", ""]);
        form.focus = 0;
        assert_eq!(form.fields[0].value, long, "nothing cut");
        // Said while typing, and again on submit.
        form.type_char('n');
        let said = form.error.clone().unwrap_or_default();
        assert!(
            said.contains("301 bytes") && said.contains("at most 255"),
            "{said}"
        );
        assert_eq!(form.submit(), None);
        let refused = form.error.clone().unwrap_or_default();
        assert!(refused.contains("at most 255"), "{refused}");
        assert_eq!(
            form.fields[0].value.len(),
            301,
            "still editable, still whole"
        );
        for _ in 0..46 {
            form.backspace();
        }
        assert_eq!(form.error, None, "255 bytes is a name");
        assert_eq!(
            form.submit(),
            Some(FormResult::Save {
                name: "n".repeat(255),
                anchor: false,
                parent: None
            })
        );
    }

    #[test]
    fn numbers_become_tenths_and_bad_numbers_name_the_field() {
        let mut form = typed(FormKind::SetCartesian, &["p", "456.6", "-1", "433.85"]);
        assert_eq!(
            form.submit(),
            Some(FormResult::SetCartesian {
                name: "p".into(),
                x: 4566,
                y: -10,
                z: 4339
            })
        );
        let mut form = typed(FormKind::SetPolar, &["q", "30", "abc", "500"]);
        assert_eq!(form.submit(), None);
        assert!(
            form.error
                .as_deref()
                .unwrap_or("")
                .starts_with("azimuth deg: 'abc'")
        );
        let mut form = typed(FormKind::SetPolar, &["q", "95", "0", "500"]);
        assert_eq!(form.submit(), None);
        assert!(
            form.error
                .as_deref()
                .unwrap_or("")
                .contains("outside -90 to 90")
        );
    }
}
