//! Jog keys in the state machine: what the jog engine's effects become, taps as bounded steps,
//! and keeping the engine's view of held keys while motion is not allowed.

use std::time::Instant;

use super::{App, Effect, KeyInput, Severity};
use crate::console::jog::{JogEffect, JogMotion, JogNotice};
use crate::link::interface::{ArmCommand, StepMove};

/// The most a tap moves in the auto-repeat fallback, tenths of millimetres (5 mm): a tap
/// cannot be told from the start of a hold when it happens, so it must be harmless.
pub const TAP_STEP_LIMIT: i32 = 50;

impl App {
    /// A refresh the jog engine made at `now` for `before` (the jog held before the tick):
    /// after the grace, with telemetry to go by, it waits for the next sample, and goes out only
    /// on one that does not contradict the jog. So a refresh never follows telemetry showing
    /// the jog stopped, slowed or replaced (see `other_client`).
    pub(super) fn hold_refresh(
        &mut self,
        before: Option<JogMotion>,
        jog: &mut Vec<JogEffect>,
        now: Instant,
    ) {
        let Some(motion) = before else {
            return;
        };
        let watched = self.truth.expects_telemetry();
        self.arm
            .others_mut()
            .hold_refresh(motion, watched, jog, now);
    }

    /// Carries out what the jog engine asked for.
    pub(super) fn apply_jog(
        &mut self,
        jog: Vec<JogEffect>,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        for effect in jog {
            match effect {
                JogEffect::Start(motion) => effects.push(Effect::Arm(ArmCommand::Jog(motion))),
                JogEffect::Stop => effects.push(Effect::Arm(ArmCommand::Stop)),
                JogEffect::Step(motion) => {
                    if let Some(step) = self.tap_step(motion) {
                        effects.push(Effect::Arm(ArmCommand::Step(step)));
                    }
                }
                JogEffect::Notice(notice) => {
                    let (text, severity) = notice_text(notice);
                    self.say(text, severity, now);
                }
            }
        }
    }

    /// A tap's step: the step mode's size, at most [`TAP_STEP_LIMIT`]. Only cartesian taps step.
    fn tap_step(&self, motion: JogMotion) -> Option<StepMove> {
        let JogMotion::Cartesian { x, y, z } = motion else {
            return None;
        };
        let size = self.keys.step().cartesian().clamp(0, TAP_STEP_LIMIT);
        Some(StepMove::Cartesian {
            dx: i32::from(x) * size,
            dy: i32::from(y) * size,
            dz: i32::from(z) * size,
        })
    }

    /// A key event that may not move the arm (overlay, screen too small, step mode, no link):
    /// if it is a jog key the engine still tracks it, latched, so once motion is allowed again
    /// it moves only after being released and pressed anew.
    pub(super) fn latch_jog_key(
        &mut self,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        let Some(action) = self
            .config
            .keymap
            .action(&key.key)
            .filter(|a| a.jog().is_some())
        else {
            return;
        };
        let jog = self.keys.jog_mut().latch(action, key.kind, now);
        self.apply_jog(jog, now, effects);
    }

    /// A key's release reaches the engine whatever is shown: it ends a hold or a latch. It may
    /// carry other modifiers than its press (shift pressed mid-hold turns the release of "w"
    /// into "W"): every jog action the key could have meant is released.
    pub(super) fn release_jog_keys(
        &mut self,
        key: &KeyInput,
        now: Instant,
        effects: &mut Vec<Effect>,
    ) {
        for action in self.config.keymap.release_candidates(&key.key) {
            let jog = self.keys.jog_mut().key(action, key.kind, now);
            self.apply_jog(jog, now, effects);
        }
    }
}

fn notice_text(notice: JogNotice) -> (String, Severity) {
    match notice {
        JogNotice::NoKeyEvents(silence) => (
            format!(
                "no key event for {}: stopped; does this terminal report key releases?",
                humane(silence)
            ),
            Severity::Warning,
        ),
        JogNotice::ReleasesMissing => (
            "a held key was pressed again with no release: this terminal does not report \
             releases; switched to the auto-repeat fallback (release and press again)"
                .into(),
            Severity::Warning,
        ),
        JogNotice::TapNeedsHold => (
            "arrows, joint and turn keys move only while held: a tap has no step".into(),
            Severity::Info,
        ),
    }
}

fn humane(d: std::time::Duration) -> String {
    if d.subsec_millis() == 0 {
        format!("{} s", d.as_secs())
    } else {
        format!("{} ms", d.as_millis())
    }
}
