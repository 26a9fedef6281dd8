//! Where each panel goes at a given terminal size, and which panels give way whole when the
//! terminal is too small for all of them, in the order docs/user-guide.md gives ("Screen
//! sizes"): the status bar and the bottom line always, then the tool, joints (beside the tool
//! panel or under it), arm and positions, log, arm view ([`VIEW_MIN_ROWS`]) and, only in spare
//! space, history ([`place_history`]) panels. A panel with fewer rows than lines shows its
//! first lines whole; a line too wide is cut at a word before a number, never inside one
//! ([`numbers::elide`](super::numbers::elide)).

use ratatui::layout::Rect;

/// The rows the joints and tool panels want (borders, a header and seven lines).
pub const TOP_ROWS: u16 = 10;
/// The rows the arm and positions panels want at 24 rows.
const MIDDLE_ROWS: u16 = 7;
/// The fewest rows worth showing for the arm and positions panels (two lines).
const MIDDLE_MIN_ROWS: u16 = 4;
/// The fewest rows worth showing for the log (one line).
const LOG_MIN_ROWS: u16 = 3;
/// The fewest rows worth showing for the joints panel under the tool panel (one joint).
const JOINTS_MIN_ROWS: u16 = 4;
/// The joints panel's share of the top row, in percent, when both panels have room.
const JOINTS_PERCENT: u16 = 58;
/// The arm panel's share of the middle row, in percent.
const ARM_PERCENT: u16 = 55;

/// The fewest rows of the arm and positions row for the arm view (ten rows of drawing).
pub const VIEW_MIN_ROWS: u16 = 12;
/// The fewest columns left of the arm view: the arm panel's wide lines (50) and borders.
const VIEW_LEFT_MIN_WIDTH: u16 = 52;
/// The fewest columns of the arm view: below this its drawings are too small to read.
const VIEW_MIN_WIDTH: u16 = 40;

/// The widths the top row's panels need (borders included).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopWidths {
    /// The tool panel with its long labels (`pos mm`).
    pub tool_long: u16,
    /// The tool panel with unit labels (`mm`).
    pub tool_short: u16,
    /// The joints panel with its name, position, velocity and torque columns.
    pub joints_comfortable: u16,
    /// The joints panel with its name and position columns only.
    pub joints_min: u16,
}

/// Every panel's place; `None` for a panel that gave way.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ScreenLayout {
    pub status: Rect,
    pub joints: Option<Rect>,
    pub tool: Option<Rect>,
    pub arm: Option<Rect>,
    pub positions: Option<Rect>,
    pub log: Option<Rect>,
    pub history: Option<Rect>,
    /// The drawing of the arm, last to get room.
    pub arm_view: Option<Rect>,
    pub bottom: Rect,
}

/// Places the panels on `area` (at least the minimum size; the caller checks).
pub fn layout(area: Rect, widths: TopWidths) -> ScreenLayout {
    let status = Rect {
        height: area.height.min(2),
        ..area
    };
    let bottom = Rect {
        y: area.bottom().saturating_sub(1),
        height: area.height.min(1),
        ..area
    };
    let mut layout = ScreenLayout {
        status,
        bottom,
        ..Default::default()
    };
    let mut free = Rect {
        y: status.bottom(),
        height: area.height.saturating_sub(3),
        ..area
    };
    let (tool_width, joints_beside) = top_split(area.width, widths);
    let top = take_rows(&mut free, TOP_ROWS);
    if joints_beside {
        let (joints, tool) = split_columns(top, area.width - tool_width);
        (layout.joints, layout.tool) = (Some(joints), Some(tool));
    } else {
        layout.tool = Some(top);
        if free.height >= JOINTS_MIN_ROWS {
            layout.joints = Some(take_rows(&mut free, TOP_ROWS));
        }
    }
    // Half the rows past 24 go to the middle row, the rest to the log.
    let extra = area.height.saturating_sub(24) / 2;
    if free.height >= MIDDLE_ROWS + extra + LOG_MIN_ROWS {
        let middle = take_rows(&mut free, MIDDLE_ROWS + extra);
        match split_off_view(middle) {
            Some((mut left, view)) => {
                layout.arm = Some(take_rows(&mut left, MIDDLE_ROWS));
                layout.positions = Some(left);
                layout.arm_view = Some(view);
            }
            None => (layout.arm, layout.positions) = split_middle(middle),
        }
        layout.log = Some(free);
    } else if free.height >= MIDDLE_MIN_ROWS {
        (layout.arm, layout.positions) = split_middle(free);
    }
    if let Some(positions) = layout.positions {
        (layout.positions, layout.history) = place_history(positions);
    }
    // Fewer rows than another panel needs stay blank.
    layout
}

/// The positions panel's width at 80x24: it keeps at least this much beside the history.
const POSITIONS_MIN_WIDTH: u16 = 36;
/// The history panel's fewest columns (labels, a short sparkline, values).
const HISTORY_MIN_WIDTH: u16 = 34;
/// The history panel's rows: borders, the TCP speed, a heading and seven joints.
pub const HISTORY_ROWS: u16 = 11;
/// The positions panel's share, in percent, when both have more than their minimum.
const POSITIONS_PERCENT: u16 = 45;

/// Splits the positions panel's place `positions` into the positions panel and, when there is
/// room for both, the history panel on its right.
pub fn place_history(positions: Rect) -> (Option<Rect>, Option<Rect>) {
    if positions.width < POSITIONS_MIN_WIDTH + HISTORY_MIN_WIDTH || positions.height < HISTORY_ROWS
    {
        return (Some(positions), None);
    }
    let kept = (positions.width * POSITIONS_PERCENT / 100).max(POSITIONS_MIN_WIDTH);
    let (positions, history) = split_columns(positions, kept);
    (Some(positions), Some(history))
}

/// The tool panel's width, and whether the joints panel fits beside it.
fn top_split(width: u16, w: TopWidths) -> (u16, bool) {
    let by_percent = width - width * JOINTS_PERCENT / 100;
    if by_percent >= w.tool_long && width - by_percent >= w.joints_comfortable {
        (by_percent, true)
    } else if width >= w.tool_long + w.joints_comfortable {
        (w.tool_long, true)
    } else if width >= w.tool_short + w.joints_min {
        (w.tool_short, true)
    } else {
        (width, false)
    }
}

/// Up to `rows` rows off the top of `free`.
fn take_rows(free: &mut Rect, rows: u16) -> Rect {
    let rows = rows.min(free.height);
    let taken = Rect {
        height: rows,
        ..*free
    };
    free.y += rows;
    free.height -= rows;
    taken
}

/// The arm view's place at the right of the middle row, and what is left of the row; `None`
/// when the row is too low or too narrow for it.
fn split_off_view(middle: Rect) -> Option<(Rect, Rect)> {
    if middle.height < VIEW_MIN_ROWS {
        return None;
    }
    let room = middle.width.checked_sub(VIEW_LEFT_MIN_WIDTH)?;
    let width = super::arm_view::wanted_width(middle.height).min(room);
    if width < VIEW_MIN_WIDTH {
        return None;
    }
    Some(split_columns(middle, middle.width - width))
}

fn split_middle(middle: Rect) -> (Option<Rect>, Option<Rect>) {
    let (arm, positions) = split_columns(middle, middle.width * ARM_PERCENT / 100);
    (Some(arm), Some(positions))
}

/// `area` cut `width` columns from its left: the left part and the rest.
fn split_columns(area: Rect, width: u16) -> (Rect, Rect) {
    let rest = Rect {
        x: area.x + width,
        width: area.width - width,
        ..area
    };
    (Rect { width, ..area }, rest)
}

#[cfg(test)]
mod tests {
    use super::*;

    const WIDTHS: TopWidths = TopWidths {
        tool_long: 35,
        tool_short: 31,
        joints_comfortable: 26,
        joints_min: 14,
    };

    fn at(width: u16, height: u16) -> ScreenLayout {
        layout(Rect::new(0, 0, width, height), WIDTHS)
    }

    #[test]
    fn at_80x24_every_panel_shows_in_its_usual_place() {
        let l = at(80, 24);
        assert_eq!(l.status, Rect::new(0, 0, 80, 2));
        assert_eq!(l.joints, Some(Rect::new(0, 2, 45, 10)));
        assert_eq!(l.tool, Some(Rect::new(45, 2, 35, 10)));
        assert_eq!(l.arm, Some(Rect::new(0, 12, 44, 7)));
        assert_eq!(l.positions, Some(Rect::new(44, 12, 36, 7)));
        assert_eq!(l.log, Some(Rect::new(0, 19, 80, 4)));
        assert_eq!(l.bottom, Rect::new(0, 23, 80, 1));
    }

    #[test]
    fn at_20_rows_the_log_gives_way_first() {
        let l = at(62, 20);
        assert!(l.log.is_none());
        assert_eq!(l.arm.map(|r| r.height), Some(7));
        assert_eq!(l.tool.map(|r| r.width), Some(35));
    }

    #[test]
    fn narrow_terminals_stack_the_joints_under_the_tool() {
        let l = at(44, 24);
        assert_eq!(l.tool, Some(Rect::new(0, 2, 44, 10)));
        assert_eq!(l.joints, Some(Rect::new(0, 12, 44, 10)));
        assert!(l.arm.is_none() && l.log.is_none());
        assert_eq!(at(45, 24).tool.map(|r| r.width), Some(31));
    }

    #[test]
    fn the_smallest_screen_keeps_the_status_the_tool_and_the_bottom_line() {
        let l = at(40, 10);
        assert_eq!(l.status, Rect::new(0, 0, 40, 2));
        assert_eq!(l.tool, Some(Rect::new(0, 2, 40, 7)));
        assert!(l.joints.is_none() && l.arm.is_none() && l.log.is_none());
        assert_eq!(l.bottom, Rect::new(0, 9, 40, 1));
    }

    #[test]
    fn the_history_takes_spare_space_beside_the_positions() {
        assert!(at(80, 24).history.is_none());
        for (width, height) in [(160, 48), (200, 60)] {
            let l = at(width, height);
            let positions = l.positions.expect("the positions panel");
            let history = l.history.expect("the history panel");
            // Beside the positions, as high, and left of the arm view when that shows.
            assert_eq!((history.x, history.y), (positions.right(), positions.y));
            assert_eq!(history.height, positions.height);
            assert!(positions.width >= POSITIONS_MIN_WIDTH && history.width >= HISTORY_MIN_WIDTH);
            let right_edge = l.arm_view.map_or(width, |view| view.x);
            assert_eq!(history.right(), right_edge);
        }
        // The smallest screen with the history (the README says so).
        assert!(at(154, 32).history.is_some());
        assert!(at(153, 32).history.is_none() && at(154, 31).history.is_none());
    }

    #[test]
    fn the_arm_view_yields_at_80x24_and_fills_the_middle_row_on_large_screens() {
        assert!(at(80, 24).arm_view.is_none());
        assert!(at(200, 30).arm_view.is_none(), "too low");
        assert!(at(90, 60).arm_view.is_none(), "too narrow");
        for (width, height) in [(160, 48), (200, 60)] {
            let l = at(width, height);
            let view = l.arm_view.expect("the arm view");
            let arm = l.arm.expect("the arm panel");
            let positions = l.positions.expect("the positions panel");
            // The arm panel above the positions, the view at their right, all as high as
            // the row.
            assert_eq!(arm.height, MIDDLE_ROWS);
            assert_eq!(positions.y, arm.bottom());
            assert_eq!(positions.bottom(), view.bottom());
            assert_eq!(arm.y, view.y);
            assert_eq!(view.right(), width);
            assert_eq!(arm.right(), view.x);
            assert!(arm.width >= VIEW_LEFT_MIN_WIDTH);
            assert_eq!(
                view.width,
                super::super::arm_view::wanted_width(view.height)
            );
            assert!(l.log.is_some());
        }
    }

    #[test]
    fn no_panel_leaves_the_screen() {
        for width in 40..=200 {
            for height in 10..=60 {
                let l = at(width, height);
                let panels = [
                    l.joints,
                    l.tool,
                    l.arm,
                    l.positions,
                    l.log,
                    l.history,
                    l.arm_view,
                ];
                for rect in panels.into_iter().flatten().chain([l.status, l.bottom]) {
                    assert!(
                        rect.right() <= width && rect.bottom() <= height,
                        "{width}x{height}"
                    );
                    assert!(
                        rect.y >= 2 || rect == l.status,
                        "{width}x{height}: {rect:?}"
                    );
                }
            }
        }
    }
}
