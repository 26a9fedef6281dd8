//! Tours in the state machine: made from the positions list, played one leg at a time or straight
//! through. Confirmed once; each leg goes the one go-to path (`App::go_to`) through the motion
//! gate, and the next starts only once the last is seen done at rest. Anything else ends the tour
//! with a message naming the leg; nothing of it starts again by itself.

use std::time::Instant;

use super::parts::Leg;
use super::{ActionKind, App, Effect, Input, KeyInput, Overlay};
use crate::console::action::Action;
use crate::console::form::{Confirm, Form, FormResult, QuestionText, TourQuestion};
use crate::console::jog::KeyKind;
use crate::console::positions::Tour;
use crate::link::interface::{ArmCommand, ArmError, ArmEvent, LinkStatus};

/// The most tours an unknown tour's name lists, of those the book has.
const TOURS_NAMED: usize = 8;

/// A book with more positions than this prefills the make form with the selected one only.
const PREFILL_ALL_UP_TO: usize = 12;

/// What in `input` ends a tour whatever its leg is doing, in words.
pub(super) fn interruption(input: &Input) -> Option<String> {
    match input {
        Input::FocusLost => Some("focus lost".into()),
        Input::Signal(_) => Some("signal".into()),
        Input::Arm(ArmEvent::Status(LinkStatus::Down { .. })) => Some("link lost".into()),
        // A failed jog to the driver, but it ends a leg too (the stop guard's stop).
        Input::Arm(ArmEvent::Failed {
            error: error @ (ArmError::GuardStoppedArm(_) | ArmError::GuardStopFailed(_)),
            ..
        }) => Some(error.to_string()),
        _ => None,
    }
}

impl App {
    /// The three tour keys (a tour waiting for its next leg is handled in [`App::tour_key`]).
    pub(super) fn on_tour_action(&mut self, action: Action, now: Instant) {
        match action {
            Action::MakeTour => self.open_make_tour(now),
            Action::PlayTour => self.open_play_tour(false, now),
            Action::TourLeg => self.open_play_tour(true, now),
            _ => {}
        }
    }

    fn open_make_tour(&mut self, now: Instant) {
        let book = self.book.positions();
        if book.is_empty() {
            self.info("no positions to tour: save some first", now);
            return;
        }
        let names: Vec<&str> = if book.len() <= PREFILL_ALL_UP_TO {
            book.names().collect()
        } else {
            self.selected_name().into_iter().collect()
        };
        self.screen.show(Overlay::Form(Form::make_tour("", &names)));
    }

    fn open_play_tour(&mut self, one_leg: bool, now: Instant) {
        let tours = self.book.positions().tours();
        let Some(first) = tours.first() else {
            let text = "no tours in the book: make one from the positions first";
            self.info(text, now);
            return;
        };
        let name = self
            .tours
            .last()
            .filter(|last| tours.iter().any(|t| t.name == *last))
            .unwrap_or(&first.name)
            .to_string();
        self.screen
            .show(Overlay::Form(Form::play_tour(&name, one_leg)));
    }

    /// A tour form submitted: one made is checked and kept; one to play checked and asked.
    pub(super) fn tour_form_submitted(
        &mut self,
        result: FormResult,
        mut form: Form,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        match result {
            FormResult::MakeTour { name, positions } => {
                if let Some((i, missing)) = self.book.positions().first_missing(&positions) {
                    form.focus = 1;
                    form.error = Some(format!("position {} '{missing}' is not in the book", i + 1));
                    self.screen.show(Overlay::Form(form));
                    return;
                }
                let legs = positions.len();
                let tour = Tour {
                    name: name.clone(),
                    positions,
                };
                let replaced = self.book.positions_mut().set_tour(tour);
                self.tours.note_last(&name);
                let verb = if replaced { "replaced" } else { "saved" };
                self.info(format!("tour '{name}' {verb}: {legs} leg(s)"), now);
                self.save_book::<&str>(&[], effects);
            }
            FormResult::PlayTour { name, one_leg } => {
                let Some(tour) = self.book.positions().tour(&name).cloned() else {
                    let known: Vec<String> = self
                        .book
                        .positions()
                        .tours()
                        .iter()
                        .map(|t| t.name.clone())
                        .collect();
                    // A long list names the first few and counts the rest.
                    let listed = QuestionText {
                        before: format!("no tour '{name}'; the book has: "),
                        list: &known,
                        separator: ", ",
                        after: String::new(),
                    };
                    form.error = Some(listed.with_first(TOURS_NAMED));
                    self.screen.show(Overlay::Form(form));
                    return;
                };
                self.tours.note_last(&name);
                if let Some(why) = self.tour_refusal(&tour) {
                    self.warn(why, now);
                    return;
                }
                if self.refuse_motion(now) {
                    return;
                }
                self.screen
                    .show(Overlay::Confirm(Confirm::Tour(TourQuestion {
                        tour,
                        one_leg,
                    })));
            }
            _ => {}
        }
    }

    /// Why `tour` cannot be played, naming the leg, or `None`.
    fn tour_refusal(&self, tour: &Tour) -> Option<String> {
        let cannot = |leg: usize, why: String| {
            format!(
                "tour '{}' cannot be played: leg {}/{}: {why}",
                tour.name,
                leg + 1,
                tour.positions.len()
            )
        };
        if let Some((i, missing)) = self.book.positions().first_missing(&tour.positions) {
            return Some(cannot(i, format!("'{missing}' is not in the book")));
        }
        tour.positions
            .iter()
            .enumerate()
            .find_map(|(i, name)| self.leg_refusal(name).map(|why| cannot(i, why)))
    }

    /// Why `name` cannot be a leg: a go-to refusal, or a name the operator lost (no re-save here).
    fn leg_refusal(&self, name: &str) -> Option<String> {
        if self.book.positions().get(name).is_none() {
            return Some(format!("'{name}' is not in the book"));
        }
        if let Some(why) = self.go_to_refusal(name) {
            return Some(why);
        }
        self.lost_by_operator(name)
            .then(|| format!("the operator does not know '{name}': go to it alone to re-save it"))
    }

    /// Yes to the tour's question: its first leg starts.
    pub(super) fn tour_confirmed(
        &mut self,
        question: TourQuestion,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        if let Some(why) = self.tour_refusal(&question.tour) {
            self.warn(why, now);
            return;
        }
        self.tours.begin(question.tour, question.one_leg);
        self.start_leg(now, effects);
    }

    /// The current leg's go-to, after the gate; refused, the tour is over.
    fn start_leg(&mut self, now: Instant, effects: &mut Vec<Effect>) {
        let Some(name) = self.tours.leg_position().map(str::to_string) else {
            self.tours.end();
            return;
        };
        let leg = self.tours.leg_text();
        let refusal = self.motion_refusal().or_else(|| self.leg_refusal(&name));
        match refusal.map_or_else(|| self.go_to(name, effects), Err) {
            Ok(()) => {
                self.tours.set_phase(Leg::Starting);
                self.info(leg, now);
            }
            Err(why) => self.tour_over(format!("{leg} not started: {why}"), now),
        }
    }

    /// Stops the current leg: the tour's message says so, not "go to 'bench' stopped".
    fn stop_leg(&mut self, effects: &mut Vec<Effect>) {
        self.motion_truth.forget_action();
        if !effects.iter().any(Effect::is_stop) {
            effects.push(Effect::Arm(ArmCommand::Stop));
        }
    }

    fn tour_over(&mut self, text: String, now: Instant) {
        self.tours.end();
        self.warn(text, now);
    }

    /// A key while a tour plays: the next-leg key goes on when a leg waits for it; any other press
    /// stops the tour and the arm. Returns whether the key was taken.
    pub(super) fn tour_key(
        &mut self,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) -> bool {
        let Some(phase) = self.tours.phase() else {
            return false;
        };
        let action = self.config.keymap.action(&key.key);
        if phase == Leg::Waiting
            && key.kind == KeyKind::Press
            && action == Some(Action::TourLeg)
            && self.screen.overlay_is_none()
        {
            if self.tours.advance() {
                self.start_leg(now, effects);
            }
            return true;
        }
        let leg = self.tours.leg_text();
        self.stop_jog(now, effects);
        self.latch_jog_key(key, now, effects);
        // A quick stop and quit still do what they do; every other key only stops.
        let own_stop = matches!(action, Some(Action::QuickStop | Action::Quit));
        if phase != Leg::Waiting && !own_stop {
            self.stop_leg(effects);
        }
        let text = format!("{leg}: stopped by a key; play it again to go on");
        self.tour_over(text, now);
        !own_stop
    }

    /// After an input, before the motion truth notes what goes out: an interruption or refusing gate ends
    /// the tour; a leg done at rest leads to the next, one that ended otherwise ends the tour.
    pub(super) fn tour_before_motion_truth(
        &mut self,
        interrupted: Option<String>,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let Some(phase) = self.tours.phase() else {
            return;
        };
        let leg = self.tours.leg_text();
        let why = interrupted
            .or_else(|| (!self.fits()).then(|| "terminal too small".to_string()))
            .or_else(|| self.motion_refusal());
        if let Some(why) = why {
            if phase != Leg::Waiting {
                self.stop_leg(effects);
            }
            self.tour_over(format!("{leg} stopped: {why}"), now);
            return;
        }
        if phase != Leg::Moving || self.leg_tracked() {
            return;
        }
        let at_rest = !self.motion_truth.is_unsettled() && self.motion_truth.expects_telemetry();
        if !at_rest {
            // The failure's own message (go to 'bench' failed: aborted) is the reason.
            let reason = self
                .message()
                .map(|(text, _)| text.to_string())
                .unwrap_or_else(|| "its end was not seen at rest".into());
            self.tour_over(format!("{leg} ended the tour: {reason}"), now);
            return;
        }
        if !self.tours.has_next() {
            let done = self.tours.leg_text();
            self.tours.end();
            self.info(format!("{done}: tour done"), now);
        } else if self.tours.one_leg() {
            self.tours.set_phase(Leg::Waiting);
            let next = match self.config.keymap.key_for(Action::TourLeg) {
                Some(key) => format!("{key} for the next leg"),
                None => "the next-leg key goes on".into(),
            };
            let text = format!("{leg} done: {next}, any other key ends the tour");
            self.info(text, now);
        } else {
            self.tours.advance();
            self.start_leg(now, effects);
        }
    }

    /// After the motion truth noted what goes out: a leg started is tracked; one dropped ends the tour.
    pub(super) fn tour_after_motion_truth(&mut self, now: Instant) {
        if self.tours.phase() != Some(Leg::Starting) {
            return;
        }
        if self.leg_tracked() {
            self.tours.set_phase(Leg::Moving);
        } else {
            let leg = self.tours.leg_text();
            self.tour_over(format!("{leg} did not start"), now);
        }
    }

    /// The go-to of the current leg is the action the motion truth tracks.
    fn leg_tracked(&self) -> bool {
        let Some(name) = self.tours.leg_position() else {
            return false;
        };
        self.motion_truth
            .action()
            .is_some_and(|a| a.kind == ActionKind::GoTo(name.to_string()))
    }
}
