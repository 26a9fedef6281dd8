//! The status bar: link (up, stale, down), key-release mode, motion (jog, action, stopping, may
//! be moving), speed, frame, step mode and joint.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

use super::theme::Theme;
use crate::console::app::{MotionShown, age_text, describe_motion};
use crate::console::jog::ReleaseMode;
use crate::console::view::View;
use crate::kortex::CodeName;
use crate::link::interface::{GuardStatus, LinkStatus};

/// What the key-release mode is, in words: the status bar always shows it.
pub fn release_mode_text(view: &View) -> String {
    match view.release_mode {
        ReleaseMode::Reported => "keys: release events".into(),
        ReleaseMode::AutoRepeat => {
            let timing = view.repeat_timing;
            match (timing.onset, timing.interval) {
                (Some(onset), Some(interval)) => format!(
                    "keys: auto-repeat fallback ({} ms, {:.0} Hz)",
                    onset.as_millis(),
                    1.0 / interval.as_secs_f64()
                ),
                _ => "keys: auto-repeat fallback".into(),
            }
        }
    }
}

/// The key-release mode without its measured timing.
fn release_mode_name(view: &View) -> &'static str {
    match view.release_mode {
        ReleaseMode::Reported => "keys: release events",
        ReleaseMode::AutoRepeat => "keys: auto-repeat fallback",
    }
}

/// The stop guard's badge, when one is required (Modbus motion).
fn guard_spans(view: &View, theme: &Theme) -> Vec<Span<'static>> {
    match &view.guard {
        None => Vec::new(),
        Some(GuardStatus::Ready { .. }) => vec![Span::styled(" GUARD OK ", theme.ok())],
        Some(GuardStatus::Starting) => vec![
            Span::styled(" NO GUARD ", theme.alarm()),
            Span::styled(" starting ", theme.warning()),
        ],
        Some(GuardStatus::Down { .. }) => vec![Span::styled(" NO GUARD ", theme.alarm())],
    }
}

/// The speed in force and the jog speed it gives (percent of the cap), e.g. `50% (125 mm/s)`.
pub fn speed_text(view: &View) -> String {
    match view.speed {
        Some(s) => {
            let mm_s = view.max_jog_speed * 1000.0 * f64::from(s) / 100.0;
            // A slow speed keeps a decimal: "0 mm/s" would read as stopped.
            if mm_s < 10.0 {
                format!("{s}% ({mm_s:.1} mm/s)")
            } else {
                format!("{s}% ({mm_s:.0} mm/s)")
            }
        }
        None => "?".into(),
    }
}

/// Two lines: the link, then keys, motion and settings (so the key-release mode always shows,
/// even at 80 columns).
pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    // The guard goes first: a missing one must show even when a long link line is cut.
    let mut spans = guard_spans(view, theme);
    match &view.link {
        LinkStatus::Up { description } => {
            // A link that went silent is not shown as healthy.
            match view.link_stale {
                Some(age) => spans.push(Span::styled(
                    format!(" LINK STALE {} ", age_text(age)),
                    theme.alarm(),
                )),
                None => spans.push(Span::styled(" LINK UP ", theme.ok())),
            }
            spans.push(Span::raw(description.clone()));
            if let Some(latency) = view.latency {
                spans.push(Span::raw(format!(
                    " {:.1} ms",
                    latency.as_secs_f64() * 1000.0
                )));
            }
        }
        LinkStatus::Connecting => spans.push(Span::styled(" CONNECTING ", theme.warning())),
        LinkStatus::Down { reason } => {
            spans.push(Span::styled(" LINK DOWN ", theme.alarm()));
            spans.push(Span::styled(format!(" {reason}"), theme.warning()));
        }
    }
    let link_line = Line::from(std::mem::take(&mut spans));
    let mut reason = None;
    match view.motion.clone() {
        MotionShown::Jog(motion) => spans.push(Span::styled(
            format!(" JOG {} ", describe_motion(motion)),
            theme.moving(),
        )),
        MotionShown::Action {
            label,
            confirmed: true,
        } => spans.push(Span::styled(format!(" MOVING: {label} "), theme.moving())),
        // Nothing comes back to say when it ends.
        MotionShown::Action {
            label,
            confirmed: false,
        } => spans.push(Span::styled(
            format!(" MAY BE MOVING: {label} "),
            theme.alarm(),
        )),
        MotionShown::Stopping => spans.push(Span::styled(" STOPPING ", theme.warning())),
        MotionShown::MayBeMoving(why) => {
            spans.push(Span::styled(" MAY BE MOVING ", theme.alarm()));
            reason = Some(why);
        }
        // The step size goes with the mode, so it shows even at 80 columns.
        MotionShown::Idle if view.step.enabled => spans.push(Span::raw(format!(
            " STEP {:.1} mm / {} deg ",
            f64::from(view.step.cartesian()) / 10.0,
            view.step.polar()
        ))),
        MotionShown::Idle => spans.push(Span::raw(" idle ")),
    }
    spans.push(Span::raw(" | "));
    let keys = spans.len();
    spans.push(Span::styled(release_mode_text(view), theme.accent()));
    spans.push(Span::raw(" | speed "));
    let speed = spans.len();
    spans.push(Span::raw(speed_text(view)));
    if view.frames {
        spans.push(Span::raw(format!(" | frame {}", view.frame.key())));
    }
    // Step mode has no joint steps: the selected joint only matters when jogging.
    if !view.step.enabled {
        spans.push(Span::raw(format!(" | J{}", view.joint)));
    }
    // The mode always shows; its measured timing only when the whole line fits.
    let width: usize = spans.iter().map(|s| s.width()).sum();
    if width > usize::from(area.width) {
        spans[keys] = Span::styled(release_mode_name(view), theme.accent());
    }
    // Still too wide: the percent alone, so the frame still shows.
    let width: usize = spans.iter().map(|s| s.width()).sum();
    if width > usize::from(area.width)
        && let Some(s) = view.speed
    {
        spans[speed] = Span::raw(format!("{s}%"));
    }
    // Why the arm may be moving, after the motion, where the line has room (the message line
    // says it too).
    if let Some(why) = reason {
        let why = Span::styled(format!("({why}) "), theme.warning());
        let width: usize = spans.iter().map(|s| s.width()).sum();
        if width + why.width() <= usize::from(area.width) {
            spans.insert(1, why);
        }
    }
    frame.render_widget(Paragraph::new(vec![link_line, Line::from(spans)]), area);
}
