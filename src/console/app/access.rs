//! Read access to the app's state, for the view and for tests: the fields stay private, so only
//! inputs change them.

use std::collections::VecDeque;

use super::{App, AppConfig, BookState, MotionTruth, Overlay, Severity, Step};
use crate::console::jog::JogEngine;
use crate::console::positions::PositionBook;
use crate::console::view::View;
use crate::kortex::{ReferenceFrame, Telemetry};
use crate::link::interface::{LinkStatus, LogEntry, TelemetrySource};

/// A joint turning faster than this (deg/s, reported) counts as the arm moving: below it, a
/// reading's noise, or motion too slow to need more than the idle frame rate.
pub const MOVING_JOINT_DEG_S: f32 = 0.5;

impl App {
    /// What one frame shows, assembled from the parts' own views.
    pub fn view(&self) -> View {
        // No panel is taller than the terminal: the book's and the log's views are cut to it.
        let rows = usize::from(self.screen.size().1);
        View {
            session: self.session_view(),
            keys: self.keys.view(),
            arm: self.arm.view(self.now),
            truth: self.truth_view(),
            book: self.book.view(rows),
            screen: self.screen.view(rows),
            tour: self.tours.view(),
        }
    }

    /// The arm moves, or may: a jog, an action, a STOP being confirmed or a doubt is shown, or
    /// the telemetry has a joint turning (whoever moves the arm). The console then draws at its
    /// full rate, so the arm view keeps up with the telemetry.
    pub fn arm_in_motion(&self) -> bool {
        !matches!(self.motion_shown(), super::MotionShown::Idle)
            || self.telemetry().is_some_and(|t| {
                t.joints
                    .iter()
                    .any(|j| j.velocity.abs() > MOVING_JOINT_DEG_S)
            })
    }

    pub fn config(&self) -> &AppConfig {
        &self.config
    }

    pub fn jog(&self) -> &JogEngine {
        self.keys.jog()
    }

    pub fn overlay(&self) -> &Overlay {
        self.screen.overlay()
    }

    /// The message on the bottom line and how bad it is.
    pub fn message(&self) -> Option<(&str, Severity)> {
        self.screen.message()
    }

    pub fn link(&self) -> &LinkStatus {
        self.arm.link()
    }

    pub fn telemetry(&self) -> Option<&Telemetry> {
        self.arm.telemetry()
    }

    /// The reference frame the console selected (the audit names it on each jog).
    pub fn frame(&self) -> ReferenceFrame {
        self.arm.frame()
    }

    /// The telemetry the driver said to expect (none until it says).
    pub fn telemetry_source(&self) -> TelemetrySource {
        self.truth
            .expected_telemetry()
            .unwrap_or(TelemetrySource::None)
    }

    /// The speed in force, percent, once the arm has said it.
    pub fn speed(&self) -> Option<u8> {
        self.arm.speed()
    }

    pub fn step(&self) -> Step {
        self.keys.step()
    }

    pub fn positions(&self) -> &PositionBook {
        self.book.positions()
    }

    pub fn book_state(&self) -> &BookState {
        self.book.state()
    }

    /// The selected position's index in name order.
    pub fn selected(&self) -> usize {
        self.book.selected()
    }

    pub fn log(&self) -> &VecDeque<std::sync::Arc<LogEntry>> {
        self.screen.log()
    }

    /// The last 30 s of telemetry (history panel).
    pub fn history(&self) -> &super::History {
        self.arm.history()
    }

    /// The log shows frames in hex.
    pub fn hex(&self) -> bool {
        self.screen.hex()
    }

    /// The terminal's size as last heard.
    pub fn size(&self) -> (u16, u16) {
        self.screen.size()
    }

    pub fn quitting(&self) -> bool {
        self.quitting
    }

    pub fn truth(&self) -> &MotionTruth {
        &self.truth
    }
}
