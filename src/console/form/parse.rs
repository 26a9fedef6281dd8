//! What a submitted form means: names by the rule, numbers in range as tenths, the form's rules.

use super::{Form, FormKind, FormResult};
use crate::talos::PositionName;

impl Form {
    pub(super) fn parse(&self) -> Result<FormResult, (usize, String)> {
        // Its first field is a kind, not a name.
        if self.kind == FormKind::Stored {
            return self.parse_stored();
        }
        let name_in = |i: usize, label: &str| {
            let name = PositionName::new(self.value(i)).map_err(|e| (i, format!("{label} {e}")))?;
            Ok::<_, (usize, String)>(name.as_str().to_string())
        };
        let name = name_in(0, "name")?;
        match self.kind {
            FormKind::Save => {
                let parent = match self.value(1) {
                    "" => None,
                    _ => Some(name_in(1, "parent")?),
                };
                if parent.as_deref() == Some(name.as_str()) {
                    return Err((1, "a position cannot be its own parent".into()));
                }
                let anchor = self.value(2) == "yes";
                if anchor && parent.is_none() {
                    return Err((2, "anchor needs a parent to move with".into()));
                }
                Ok(FormResult::Save {
                    name,
                    anchor,
                    parent,
                })
            }
            FormKind::SetPolar => Ok(FormResult::SetPolar {
                name,
                delta: tenths(self, 1, -90.0, 90.0)?,
                azimuth: tenths(self, 2, -360.0, 360.0)?,
                radius: tenths(self, 3, 0.0, 2000.0)?,
            }),
            FormKind::SetCartesian => Ok(FormResult::SetCartesian {
                name,
                x: tenths(self, 1, -2000.0, 2000.0)?,
                y: tenths(self, 2, -2000.0, 2000.0)?,
                z: tenths(self, 3, -2000.0, 2000.0)?,
            }),
            FormKind::MakeTour => Ok(FormResult::MakeTour {
                name,
                positions: self.tour_legs()?,
            }),
            FormKind::PlayTour { one_leg } => Ok(FormResult::PlayTour { name, one_leg }),
            FormKind::Rename => {
                let from = self.original.clone().unwrap_or_default();
                if from == name {
                    return Err((0, format!("'{name}' is its name already")));
                }
                Ok(FormResult::Rename { from, to: name })
            }
            // Taken above, before the name.
            FormKind::Stored => self.parse_stored(),
        }
    }
}

/// Field `i` as a number within `min..=max`, in tenths.
fn tenths(form: &Form, i: usize, min: f64, max: f64) -> Result<i32, (usize, String)> {
    let field = &form.fields[i];
    let text = field.value.trim();
    let value: f64 = text
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| (i, format!("{}: '{text}' is not a number", field.label)))?;
    if !(min..=max).contains(&value) {
        return Err((
            i,
            format!("{}: {value} is outside {min} to {max}", field.label),
        ));
    }
    Ok((value * 10.0).round() as i32)
}
