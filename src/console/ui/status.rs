//! The status bar: link (up, stale, down), key-release mode, motion (jog, action, stopping, may
//! be moving), speed, frame, step mode and joint.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};

use super::numbers;
use super::theme::Theme;
use crate::console::action::Action;
use crate::console::app::{MotionShown, age_text, describe_motion, singularity_text};
use crate::console::jog::{JogMotion, ReleaseMode};
use crate::console::view::View;
use crate::kortex::CodeName;
use crate::link::interface::{GuardStatus, LinkStatus};

/// What the key-release mode is, in words: the status bar always shows it.
pub fn release_mode_text(view: &View) -> String {
    let timing = view.keys.repeat_timing;
    match (view.keys.release_mode, timing.onset, timing.interval) {
        (ReleaseMode::AutoRepeat, Some(onset), Some(interval)) => format!(
            "{} ({} ms, {:.0} Hz)",
            release_mode_name(view),
            onset.as_millis(),
            1.0 / interval.as_secs_f64()
        ),
        _ => release_mode_name(view).into(),
    }
}

/// The key-release mode without its measured timing.
fn release_mode_name(view: &View) -> &'static str {
    match view.keys.release_mode {
        ReleaseMode::Reported => "keys: release events",
        ReleaseMode::AutoRepeat => "keys: auto-repeat fallback",
    }
}

/// The built-in simulator's badge; none for a real link, whose address the line shows.
fn simulated_span(view: &View, theme: &Theme) -> Option<Span<'static>> {
    let badge = Span::styled(" SIMULATED ARM ", theme.simulated());
    view.session.simulated.then_some(badge)
}

/// The stop guard's badge, when one is required (every real link).
fn guard_spans(view: &View, theme: &Theme) -> Vec<Span<'static>> {
    match &view.arm.guard {
        None => Vec::new(),
        Some(GuardStatus::Ready { .. }) => vec![Span::styled(" GUARD OK ", theme.ok())],
        Some(GuardStatus::Starting) => vec![
            Span::styled(" NO GUARD ", theme.alarm()),
            Span::styled(" starting ", theme.warning()),
        ],
        Some(GuardStatus::Down { .. }) => vec![Span::styled(" NO GUARD ", theme.alarm())],
    }
}

/// The arm profile's name (`--arm cell3`), before the link: which cell the keys move.
fn arm_name_span(view: &View) -> Option<Span<'static>> {
    const ARM_NAME_WIDTH: usize = 16;
    let name = crate::text::shown(view.session.arm_name.as_deref()?);
    Some(Span::raw(format!(
        " arm {} ",
        numbers::elide(&name, ARM_NAME_WIDTH)
    )))
}

/// The tour being played, after the motion: `TOUR 2/5 → bench`, or `TOUR 2/5 at bench: N next
/// leg` (the next-leg key of the keymap in use) when one leg at a time waits for its key;
/// narrow, `TOUR 2/5`.
fn tour_spans(view: &View, theme: &Theme, cut: Cut) -> Vec<Span<'static>> {
    let Some(tour) = &view.tour else {
        return Vec::new();
    };
    let count = format!("TOUR {}/{}", tour.leg, tour.legs);
    let to = crate::text::shown(&tour.to);
    let text = match (cut.words, tour.waiting) {
        (false, _) => format!(" {count} "),
        (true, false) => format!(" {count} → {to} "),
        (true, true) => {
            let key = view.session.keymap.key_for(Action::TourLeg);
            let key = key.map(|key| format!("{key} ")).unwrap_or_default();
            format!(" {count} at {to}: {key}next leg ")
        }
    };
    vec![Span::styled(text, theme.accent())]
}

/// The speed in force and the tool speed cap it puts in force (percent of the cap), e.g.
/// `50% (≤125 mm/s)`; where no telemetry lets the console watch the cap, it says so:
/// `50% (≤125 mm/s, cap not watched)`.
pub fn speed_text(view: &View) -> String {
    speed_part(view, true)
}

/// [`speed_text`], with or without the tool speed: `50%`, `50% (cap not watched)`.
fn speed_part(view: &View, mm_s: bool) -> String {
    let percent = view
        .arm
        .speed
        .map_or_else(|| "?".to_string(), |s| format!("{s}%"));
    let cap = view.arm.speed.filter(|_| mm_s).map(|s| {
        let mm_s = view.session.cap.tool_speed_mm_s(s);
        // A slow speed keeps a decimal: "0 mm/s" would read as stopped.
        let decimals = usize::from(mm_s < 10.0);
        format!("≤{mm_s:.decimals$} mm/s")
    });
    let unwatched =
        (view.motion_status.cap_watched == Some(false)).then(|| "cap not watched".into());
    let notes: Vec<String> = cap.into_iter().chain(unwatched).collect();
    match notes.is_empty() {
        true => percent,
        false => format!("{percent} ({})", notes.join(", ")),
    }
}

/// An orientation jog in words, with its rate and frame: `turning +Rz 15.0 deg/s (tool frame)`.
/// The rate is the one the driver commands: the speed in force of the maximum, at most the
/// arm's configured angular limit when telemetry reports one.
pub fn turn_text(view: &View, motion: JogMotion) -> String {
    let axes = describe_motion(motion);
    let Some(speed) = view.arm.speed else {
        return format!("turning {axes} ({} frame)", view.arm.frame.key());
    };
    let wanted = f64::from(view.session.cap.turn_rate(speed));
    let arm_limit = view
        .arm
        .telemetry
        .as_ref()
        .map(|t| f64::from(t.speed_limits.angular))
        .filter(|limit| limit.is_finite() && *limit > 0.0);
    let rate = arm_limit.map_or(wanted, |limit| wanted.min(limit));
    format!(
        "turning {axes} {} deg/s ({} frame)",
        numbers::fixed(rate, 1),
        view.arm.frame.key()
    )
}

/// Two lines: the link, then keys, motion and settings (so the key-release mode always shows,
/// even at the minimum width). Each line uses the whole width: parts give way only when the
/// line is too wide for the terminal, the least needed first, and none is ever cut inside.
pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let width = usize::from(area.width);
    let lines = vec![
        link_line(view, theme, width),
        motion_line(view, theme, width),
    ];
    super::lines::draw(frame.buffer_mut(), area, None, &lines);
}

fn spans_width(spans: &[Span]) -> usize {
    spans.iter().map(|s| numbers::width(&s.content)).sum()
}

/// The simulated-arm badge, the guard, the link's state and what it is, then the latency. The
/// badges go first: a simulated arm or a missing guard must show however narrow the line. The
/// description is elided (never inside a number) before the state is; the latency goes before
/// the description is elided.
fn link_line(view: &View, theme: &Theme, width: usize) -> Line<'static> {
    // Which arm the keys move comes first of all: a demo must never pass for a real cell.
    // A recording played back says so before anything: nothing on this screen is live.
    let replay =
        (view.session.replay.as_ref()).map(|r| Span::styled(format!(" {r} "), theme.simulated()));
    let mut badges: Vec<_> = replay.into_iter().collect();
    badges.extend(simulated_span(view, theme));
    badges.extend(guard_spans(view, theme));
    badges.extend(arm_name_span(view));
    if view.session.recording_off {
        badges.push(Span::styled(" REC OFF ", theme.warning()));
    }
    let (detail, detail_style, latency) = match &view.arm.link {
        LinkStatus::Up { description } => {
            // A link that went silent is not shown as healthy.
            badges.push(match view.motion_status.link_stale {
                Some(age) => Span::styled(format!(" LINK STALE {} ", age_text(age)), theme.alarm()),
                None => Span::styled(" LINK UP ", theme.ok()),
            });
            let latency = view
                .arm
                .latency
                .map(|l| format!(" {} ms", numbers::fixed(l.as_secs_f64() * 1000.0, 1)));
            (description.clone(), Style::default(), latency)
        }
        LinkStatus::Connecting => {
            badges.push(Span::styled(" CONNECTING ", theme.warning()));
            (String::new(), Style::default(), None)
        }
        LinkStatus::Down { reason } => {
            badges.push(Span::styled(" LINK DOWN ", theme.alarm()));
            (format!(" {reason}"), theme.warning(), None)
        }
    };
    let room = width.saturating_sub(spans_width(&badges));
    let detail_width = numbers::width(&detail);
    let mut spans = badges;
    match latency {
        Some(latency) if detail_width + numbers::width(&latency) <= room => {
            spans.push(Span::styled(detail, detail_style));
            spans.push(Span::raw(latency));
        }
        _ => spans.push(Span::styled(numbers::elide(&detail, room), detail_style)),
    }
    Line::from(spans)
}

/// How much of the second line gives way, in order: why the arm may be moving (the message
/// line says it too), the measured auto-repeat timing, the speed's cap in mm/s (`cap not
/// watched` stays with the percentage), the words around the key-release mode and the settings
/// (and every warning but the first: joints near a limit, then the singularity), the joint, the
/// frame, the speed, the first warning; the motion and the key-release mode never.
#[derive(Debug, Clone, Copy)]
struct Cut {
    reason: bool,
    timing: bool,
    mm_s: bool,
    words: bool,
    joint: bool,
    frame: bool,
    speed: bool,
    limit: bool,
}

/// The line with the first `given_up` parts (0 to 8, in [`Cut`]'s order) given up: each keeps
/// what the one before it keeps, less one more part.
fn cut(given_up: usize) -> Cut {
    Cut {
        reason: given_up < 1,
        timing: given_up < 2,
        mm_s: given_up < 3,
        words: given_up < 4,
        joint: given_up < 5,
        frame: given_up < 6,
        speed: given_up < 7,
        limit: given_up < 8,
    }
}

/// The motion, the key-release mode and the settings, as much of them as fits `width`.
fn motion_line(view: &View, theme: &Theme, width: usize) -> Line<'static> {
    let candidates = (0..=8).map(|given_up| motion_spans(view, theme, cut(given_up)));
    let mut last = Vec::new();
    for spans in candidates {
        if spans_width(&spans) <= width {
            return Line::from(spans);
        }
        last = spans;
    }
    // Only the motion and the mode left, and still too wide: the motion's label is elided.
    let rest = spans_width(last.get(1..).unwrap_or_default());
    if let Some(first) = last.first_mut() {
        let room = width.saturating_sub(rest);
        first.content = numbers::elide(&first.content, room).into();
    }
    Line::from(last)
}

fn motion_spans(view: &View, theme: &Theme, cut: Cut) -> Vec<Span<'static>> {
    let mut reason = None;
    let (motion, style) = match view.motion_status.motion.clone() {
        MotionShown::Jog(motion @ JogMotion::Orientation { .. }) => {
            (format!(" JOG {} ", turn_text(view, motion)), theme.moving())
        }
        MotionShown::Jog(motion) => (format!(" JOG {} ", describe_motion(motion)), theme.moving()),
        MotionShown::Action {
            label,
            confirmed: true,
        } => (format!(" MOVING: {label} "), theme.moving()),
        // Nothing comes back to say when it ends.
        MotionShown::Action {
            label,
            confirmed: false,
        } => (format!(" MAY BE MOVING: {label} "), theme.alarm()),
        MotionShown::Stopping => (" STOPPING ".into(), theme.warning()),
        MotionShown::MovedByAnotherClient => (" MOVED BY ANOTHER CLIENT ".into(), theme.alarm()),
        MotionShown::MayBeMoving(why) => {
            reason = Some(why);
            (" MAY BE MOVING ".into(), theme.alarm())
        }
        // The step size goes with the mode, so it shows at any width.
        MotionShown::Idle if view.keys.step.enabled => {
            let step = view.keys.step;
            let mm = numbers::fixed(f64::from(step.cartesian()) / 10.0, 1);
            (
                format!(" STEP {mm} mm / {} deg ", step.polar()),
                Style::default(),
            )
        }
        MotionShown::Idle => (" idle ".into(), Style::default()),
    };
    let mut spans = vec![Span::styled(motion, style)];
    // Why the arm may be moving, after the motion (the message line says it too).
    if let Some(why) = reason.filter(|_| cut.reason) {
        spans.push(Span::styled(format!("({why}) "), theme.warning()));
    }
    spans.extend(tour_spans(view, theme, cut));
    let separator = if cut.words { " | " } else { " " };
    // A joint near its limit or a singularity, after the motion: the next jog may be the one
    // that stops on it or turns a joint fast for little tool motion.
    let mut text = warnings(view);
    text.truncate(if cut.words { text.len() } else { 1 });
    if cut.limit && !text.is_empty() {
        spans.push(Span::styled(
            format!(" {} ", text.join(", ")),
            theme.warning(),
        ));
    }
    spans.push(Span::raw(separator));
    let mode = match (cut.timing, cut.words) {
        (true, _) => release_mode_text(view),
        (false, true) => release_mode_name(view).to_string(),
        (false, false) => release_mode_short(view).to_string(),
    };
    spans.push(Span::styled(mode, theme.accent()));
    if cut.speed {
        let speed = speed_part(view, cut.mm_s);
        let label = if cut.words { "speed " } else { "" };
        spans.push(Span::raw(format!("{separator}{label}{speed}")));
    }
    if view.session.frames && cut.frame {
        let (label, frame) = (if cut.words { "frame " } else { "" }, view.arm.frame.key());
        spans.push(Span::raw(format!("{separator}{label}{frame}")));
    }
    // Step mode has no joint steps: the selected joint only matters when jogging.
    if !view.keys.step.enabled && cut.joint {
        spans.push(Span::raw(format!("{separator}J{}", view.keys.joint)));
    }
    spans
}

/// What the fence says, the joints near a limit, the nearest first, then the arm near a
/// singularity: one warning each. Narrow, only the first shows.
fn warnings(view: &View) -> Vec<String> {
    let fence = view.arm.fence.iter().cloned();
    fence
        .chain(view.arm.near_limits.iter().map(|n| n.text()))
        .chain(view.arm.near_singularity.map(singularity_text))
        .collect()
}

fn release_mode_short(view: &View) -> &'static str {
    match view.keys.release_mode {
        ReleaseMode::Reported => "release",
        ReleaseMode::AutoRepeat => "auto-repeat",
    }
}
