//! The form that starts a stored action or sequence by id, checked before anything is asked.

use super::{Field, Form, FormKind, FormResult};
use crate::kortex::commands::{STORED_IDS, stored_id};
use crate::kortex::{Stored, StoredMotion};

/// Where a real arm's ids are: the form says so under its fields (within a dialog's 70 columns).
pub const STORED_NOTE: &str =
    "kind: action or sequence; ids are on the arm's Web App, Actions page";

/// The fields, in order.
const KIND: usize = 0;
const ID: usize = 1;

impl Form {
    /// The stored action form: the kind prefilled `action`, the id empty and focused.
    pub fn stored() -> Form {
        Form {
            kind: FormKind::Stored,
            fields: vec![Field::text("kind", "action"), Field::text("id", "")],
            focus: ID,
            error: None,
            original: None,
            note: Some(STORED_NOTE),
        }
    }

    pub(super) fn parse_stored(&self) -> Result<FormResult, (usize, String)> {
        let kind = self.value(KIND);
        let motion = match kind.to_ascii_lowercase().as_str() {
            "action" | "a" => StoredMotion::Action,
            "sequence" | "s" => StoredMotion::Sequence,
            "" => return Err((KIND, "kind is empty: type action or sequence".into())),
            _ => {
                return Err((
                    KIND,
                    format!("kind: '{kind}' is neither action nor sequence"),
                ));
            }
        };
        let text = self.value(ID);
        let (first, last) = (STORED_IDS.start(), STORED_IDS.end());
        if text.is_empty() {
            return Err((
                ID,
                format!("id is empty: type a whole number from {first} to {last}"),
            ));
        }
        let number: i128 = text.parse().map_err(|_| {
            (
                ID,
                format!("id: '{text}' is not a whole number from {first} to {last}"),
            )
        })?;
        let id = stored_id(number).map_err(|e| (ID, format!("id: {e}")))?;
        Ok(FormResult::Stored(Stored { motion, id }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn submitted(kind: &str, id: &str) -> Result<FormResult, String> {
        let mut form = Form::stored();
        form.fields[KIND].value = kind.into();
        form.fields[ID].value = id.into();
        form.submit()
            .ok_or_else(|| form.error.clone().unwrap_or_default())
    }

    #[test]
    fn kind_and_id_give_the_stored_run() {
        let action = Stored {
            motion: StoredMotion::Action,
            id: 5,
        };
        assert_eq!(submitted("action", "5"), Ok(FormResult::Stored(action)));
        assert_eq!(submitted(" A ", " 5 "), Ok(FormResult::Stored(action)));
        let sequence = Stored {
            motion: StoredMotion::Sequence,
            id: 65535,
        };
        assert_eq!(
            submitted("Sequence", "65535"),
            Ok(FormResult::Stored(sequence))
        );
        assert_eq!(
            submitted("s", "1"),
            Ok(FormResult::Stored(Stored {
                motion: StoredMotion::Sequence,
                id: 1
            }))
        );
    }

    #[test]
    fn a_bad_kind_or_id_names_what_was_wrong_and_focuses_it() {
        for (kind, id, said, field) in [
            (
                "trajectory",
                "5",
                "kind: 'trajectory' is neither action nor sequence",
                KIND,
            ),
            ("", "5", "kind is empty: type action or sequence", KIND),
            (
                "action",
                "",
                "id is empty: type a whole number from 1 to 65535",
                ID,
            ),
            ("action", "0", "id: 0 is outside 1 to 65535", ID),
            ("action", "65536", "id: 65536 is outside 1 to 65535", ID),
            ("action", "-3", "id: -3 is outside 1 to 65535", ID),
            (
                "action",
                "5.5",
                "id: '5.5' is not a whole number from 1 to 65535",
                ID,
            ),
            (
                "action",
                "five",
                "id: 'five' is not a whole number from 1 to 65535",
                ID,
            ),
        ] {
            let mut form = Form::stored();
            form.fields[KIND].value = kind.into();
            form.fields[ID].value = id.into();
            form.focus = 1 - field;
            assert_eq!(form.submit(), None, "{kind} {id}");
            assert_eq!(form.error.as_deref(), Some(said), "{kind} {id}");
            assert_eq!(form.focus, field, "{kind} {id}");
            assert_eq!(form.fields[ID].value, id, "nothing typed is lost");
        }
    }
}
