//! The tour being played: which tour, which leg, and where it is (see `app/tour.rs`).

use crate::console::positions::Tour;

/// Where the current leg is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(in crate::console::app) enum Leg {
    /// Its go-to was emitted by this input: it is tracked once the motion truth has noted it.
    Starting,
    /// Its go-to is tracked (`MOVING: GOTO bench`) until its end.
    Moving,
    /// Done at rest; one leg at a time, the next-leg key goes on.
    Waiting,
}

#[derive(Debug, Clone, PartialEq)]
struct Run {
    tour: Tour,
    one_leg: bool,
    /// The current leg, 0-based.
    leg: usize,
    phase: Leg,
}

/// The run in progress, if any, and the last tour made or played.
#[derive(Debug, Clone, Default)]
pub(in crate::console::app) struct Tours {
    run: Option<Run>,
    last: Option<String>,
}

/// What the status bar shows of a tour: `TOUR 2/5 → bench`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TourView {
    pub name: String,
    /// The current leg, 1-based, of `legs`.
    pub leg: usize,
    pub legs: usize,
    /// The position the leg goes to.
    pub to: String,
    /// The leg is done and the next-leg key goes on (one leg at a time).
    pub waiting: bool,
}

impl Tours {
    pub(in crate::console::app) fn view(&self) -> Option<TourView> {
        let run = self.run.as_ref()?;
        Some(TourView {
            name: run.tour.name.clone(),
            leg: run.leg + 1,
            legs: run.tour.positions.len(),
            to: run.tour.positions.get(run.leg).cloned().unwrap_or_default(),
            waiting: run.phase == Leg::Waiting,
        })
    }

    pub(in crate::console::app) fn last(&self) -> Option<&str> {
        self.last.as_deref()
    }

    pub(in crate::console::app) fn note_last(&mut self, name: &str) {
        self.last = Some(name.to_string());
    }

    pub(in crate::console::app) fn begin(&mut self, tour: Tour, one_leg: bool) {
        self.last = Some(tour.name.clone());
        self.run = Some(Run {
            tour,
            one_leg,
            leg: 0,
            phase: Leg::Starting,
        });
    }

    pub(in crate::console::app) fn phase(&self) -> Option<Leg> {
        self.run.as_ref().map(|r| r.phase)
    }

    pub(in crate::console::app) fn set_phase(&mut self, phase: Leg) {
        if let Some(run) = self.run.as_mut() {
            run.phase = phase;
        }
    }

    pub(in crate::console::app) fn one_leg(&self) -> bool {
        self.run.as_ref().is_some_and(|r| r.one_leg)
    }

    /// The current leg's position, while it starts (it names a go-to over Modbus).
    pub(in crate::console::app) fn starting_leg(&self) -> Option<String> {
        let run = self.run.as_ref().filter(|r| r.phase == Leg::Starting)?;
        run.tour.positions.get(run.leg).cloned()
    }

    pub(in crate::console::app) fn leg_position(&self) -> Option<&str> {
        let run = self.run.as_ref()?;
        run.tour.positions.get(run.leg).map(String::as_str)
    }

    /// `tour 'rounds' leg 2/3 → bench`, for messages.
    pub(in crate::console::app) fn leg_text(&self) -> String {
        match self.view() {
            Some(v) => format!("tour '{}' leg {}/{} → {}", v.name, v.leg, v.legs, v.to),
            None => "tour".into(),
        }
    }

    pub(in crate::console::app) fn has_next(&self) -> bool {
        self.run
            .as_ref()
            .is_some_and(|r| r.leg + 1 < r.tour.positions.len())
    }

    /// On to the next leg; `false` (and the run kept) when this was the last.
    pub(in crate::console::app) fn advance(&mut self) -> bool {
        let Some(run) = self.run.as_mut() else {
            return false;
        };
        if run.leg + 1 >= run.tour.positions.len() {
            return false;
        }
        run.leg += 1;
        run.phase = Leg::Starting;
        true
    }

    /// The tour is over (done, stopped or failed): nothing of it starts again by itself.
    pub(in crate::console::app) fn end(&mut self) {
        self.run = None;
    }
}
