//! The bottom line: the latest message, or the most used keys of the active keymap.
//!
//! The keys come in groups, one per family of actions (`w/s/a/d/r/f jog`, `arrows pan`,
//! `space stop`): each key by its keymap name, never run together. A line too narrow for every
//! group drops whole groups, the least needed first; a key name is never cut.

use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;

use super::theme::Theme;
use crate::console::action::Action;
use crate::console::app::{LinkActions, Severity};
use crate::console::keymap::{KeyName, Keymap, NamedKey};
use crate::console::view::View;

const GROUP_GAP: &str = "  ";

/// One footer group: its label, its actions (one key shown for each) and how much it is needed
/// (0 first: dropped last).
struct Group {
    label: &'static str,
    actions: &'static [Action],
    priority: u8,
}

/// The groups in the order they are shown.
const GROUPS: [Group; 13] = {
    use Action as A;
    const fn group(label: &'static str, actions: &'static [Action], priority: u8) -> Group {
        Group {
            label,
            actions,
            priority,
        }
    }
    [
        group(
            "jog",
            &[
                A::JogXPlus,
                A::JogXMinus,
                A::JogYPlus,
                A::JogYMinus,
                A::JogZPlus,
                A::JogZMinus,
            ],
            3,
        ),
        // Kept after pan: on an arm with both, pan is the older and more used family.
        group(
            "turn",
            &[
                A::JogRxPlus,
                A::JogRxMinus,
                A::JogRyPlus,
                A::JogRyMinus,
                A::JogRzPlus,
                A::JogRzMinus,
            ],
            5,
        ),
        group(
            "pan",
            &[
                A::PanAzimuthPlus,
                A::PanAzimuthMinus,
                A::PanAltitudePlus,
                A::PanAltitudeMinus,
            ],
            4,
        ),
        group("joint", &[A::JointPlus, A::JointMinus], 10),
        group("stop", &[A::Stop], 0),
        group("speed", &[A::SpeedUp, A::SpeedDown], 8),
        group("step", &[A::StepMode], 9),
        group("home", &[A::Home], 7),
        // The least needed: dropped first.
        group("stored", &[A::StoredAction], 12),
        group("save", &[A::SavePosition], 6),
        group("go to", &[A::GoToPosition], 11),
        group("help", &[A::Help], 1),
        group("quit", &[A::Quit], 2),
    ]
};

/// The four arrow keys, which the footer calls "arrows" when they are a group's keys.
const ARROWS: [NamedKey; 4] = [
    NamedKey::Right,
    NamedKey::Left,
    NamedKey::Up,
    NamedKey::Down,
];

/// The keys of a recording played back (`armjog replay`): none of them is the console's.
pub const REPLAY_KEYS: &str =
    "space pause  \u{2190}/\u{2192} 1 s (shift 10 s)  +/- speed  Home/End  q quit";

pub fn draw(frame: &mut Frame, area: Rect, view: &View, theme: &Theme) {
    let line = match &view.screen.message {
        Some((text, severity)) => {
            let style = match severity {
                Severity::Info => theme.accent(),
                Severity::Warning => theme.warning(),
                Severity::Error => theme.alarm(),
            };
            Line::styled(text.clone(), style)
        }
        None if view.session.replay.is_some() => Line::styled(REPLAY_KEYS, theme.dim()),
        None => {
            let session = &view.session;
            let keys = footer(
                &session.keymap,
                session.link_actions,
                usize::from(area.width),
            );
            Line::styled(keys, theme.dim())
        }
    };
    super::lines::draw(frame.buffer_mut(), area, None, &[line]);
}

/// The key groups of `keymap` that fit in `width` columns, in display order. Only actions the
/// links carry (`link_actions`) get a key: a group of none is left out (the joint keys without a Talos
/// operator in the ICD dialect, the turn keys and the stored action key without a Modbus link,
/// the save key where saving cannot work, the go-to key where no link moves to a saved
/// position).
pub fn footer(keymap: &Keymap, link_actions: LinkActions, width: usize) -> String {
    let groups: Vec<(u8, String)> = GROUPS
        .iter()
        .filter_map(|group| Some((group.priority, group_text(keymap, link_actions, group)?)))
        .collect();
    let mut by_need: Vec<usize> = (0..groups.len()).collect();
    by_need.sort_by_key(|&i| groups[i].0);
    let mut shown = vec![false; groups.len()];
    let mut used = 0;
    for i in by_need {
        let gap = if used == 0 { 0 } else { GROUP_GAP.len() };
        let cost = gap + groups[i].1.chars().count();
        if used + cost <= width {
            shown[i] = true;
            used += cost;
        }
    }
    groups
        .into_iter()
        .zip(shown)
        .filter(|(_, shown)| *shown)
        .map(|((_, text), _)| text)
        .collect::<Vec<_>>()
        .join(GROUP_GAP)
}

/// `keys label`, e.g. `w/s/a/d/r/f jog`; `None` when the keymap binds none of its actions that
/// the links carry.
fn group_text(keymap: &Keymap, link_actions: LinkActions, group: &Group) -> Option<String> {
    let keys: Vec<KeyName> = group
        .actions
        .iter()
        .filter(|action| link_actions.carries(**action))
        .filter_map(|action| keymap.key_for(*action))
        .collect();
    if keys.is_empty() {
        return None;
    }
    let arrows = keys.len() == ARROWS.len()
        && ARROWS
            .iter()
            .all(|arrow| keys.contains(&KeyName::named(*arrow)));
    let spelled = if arrows {
        "arrows".to_string()
    } else {
        let names: Vec<String> = keys.iter().map(KeyName::to_string).collect();
        // A separator no key name contains: `/` reads best, but not next to `kp/`.
        let separator = ["/", ",", " "]
            .into_iter()
            .find(|sep| !names.iter().any(|name| name.contains(sep)))
            .unwrap_or(" ");
        names.join(separator)
    };
    Some(format!("{spelled} {}", group.label))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_keymap() -> Keymap {
        match Keymap::builtin("default") {
            Some(keymap) => keymap,
            None => panic!("no default keymap"),
        }
    }

    #[test]
    fn a_wide_footer_shows_every_group_in_order() {
        let text = footer(&default_keymap(), LinkActions::ALL, 200);
        assert_eq!(
            text,
            "w/s/a/d/r/f jog  i/m/l/b/e/z turn  arrows pan  k/j joint  space stop  +/- speed  \
             t step  h home  A stored  p save  o go to  ? help  q quit"
        );
    }

    #[test]
    fn a_narrow_footer_drops_whole_groups_least_needed_first() {
        let keymap = default_keymap();
        let full = footer(&keymap, LinkActions::ALL, 200);
        for width in 0..=full.len() {
            let text = footer(&keymap, LinkActions::ALL, width);
            assert!(text.chars().count() <= width, "{width}: {text}");
            for group in text.split(GROUP_GAP) {
                assert!(full.contains(group), "{width}: {group} is cut");
            }
            if width >= "space stop".len() {
                assert!(text.contains("space stop"), "{width}: {text}");
            }
        }
        assert_eq!(
            footer(&keymap, LinkActions::ALL, 30),
            "space stop  ? help  q quit"
        );
    }

    #[test]
    fn the_turn_group_drops_after_pan_and_before_stop_help_and_quit() {
        let keymap = default_keymap();
        let essentials = "w/s/a/d/r/f jog  arrows pan  space stop  ? help  q quit";
        let turn = "  i/m/l/b/e/z turn";
        // Just wide enough for the turn group beside pan and the essentials: it is shown.
        assert_eq!(
            footer(&keymap, LinkActions::ALL, essentials.len() + turn.len()),
            "w/s/a/d/r/f jog  i/m/l/b/e/z turn  arrows pan  space stop  ? help  q quit"
        );
        // One column less: the turn group goes (smaller groups may fill the room), pan stays.
        let narrower = footer(&keymap, LinkActions::ALL, essentials.len() + turn.len() - 1);
        assert!(!narrower.contains("turn"), "{narrower}");
        for group in essentials.split(GROUP_GAP) {
            assert!(narrower.contains(group), "{group} dropped: {narrower}");
        }
    }

    #[test]
    fn turns_that_the_link_cannot_carry_are_not_offered() {
        let offered = LinkActions {
            turn: false,
            ..LinkActions::ALL
        };
        let text = footer(&default_keymap(), offered, 200);
        assert!(!text.contains("turn"), "{text}");
        assert!(text.starts_with("w/s/a/d/r/f jog  arrows pan"), "{text}");
    }

    #[test]
    fn joint_jogs_that_the_links_cannot_carry_are_not_offered() {
        let offered = LinkActions {
            joint: false,
            ..LinkActions::ALL
        };
        let text = footer(&default_keymap(), offered, 200);
        assert!(!text.contains("joint"), "{text}");
        assert!(text.contains("arrows pan  space stop"), "{text}");
    }

    #[test]
    fn saving_that_cannot_work_is_not_offered() {
        let offered = LinkActions {
            save: false,
            ..LinkActions::ALL
        };
        let text = footer(&default_keymap(), offered, 200);
        assert!(!text.contains("save"), "{text}");
        assert!(text.contains("h home  A stored  o go to"), "{text}");
    }

    #[test]
    fn a_go_to_that_cannot_work_is_not_offered() {
        let offered = LinkActions {
            go_to: false,
            ..LinkActions::ALL
        };
        let text = footer(&default_keymap(), offered, 200);
        assert!(!text.contains("go to"), "{text}");
        assert!(text.contains("p save  ? help"), "{text}");
    }

    #[test]
    fn stored_actions_that_the_link_cannot_run_are_not_offered() {
        let offered = LinkActions {
            stored: false,
            ..LinkActions::ALL
        };
        let text = footer(&default_keymap(), offered, 200);
        assert!(!text.contains("stored"), "{text}");
        assert!(text.contains("h home  p save"), "{text}");
        // The least needed group: the first dropped when the line is short.
        let full = footer(&default_keymap(), LinkActions::ALL, 200);
        let short = footer(&default_keymap(), LinkActions::ALL, full.len() - 1);
        assert!(
            full.contains("A stored") && !short.contains("A stored"),
            "{short}"
        );
    }
}
