//! Long names on the screen (insta snapshots): the positions panel elides them with `…` and
//! keeps the coordinates in view; the form keeps the typing end in view and refuses a name
//! over 255 bytes with the limit.

use std::time::Instant;

use armjog::console::app::{App, Input, Overlay};
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::PositionBook;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::link::interface::ArmEvent;
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::app_support;

use app_support::*;

/// 300 characters: "long-" then digits, so a cut shows where it fell.
fn long_name() -> String {
    let mut name = String::from("long-");
    let mut i = 0;
    while name.len() < 300 {
        name.push(char::from(b'0' + (i % 10) as u8));
        i += 1;
    }
    name
}

/// A book with a 300-character name (selected), an anchored one whose parent is that name,
/// an unknown one, and a short one, on a Talos operator.
fn app_with_long_names() -> (App, Instant) {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    let long = long_name();
    let mut book = PositionBook::new();
    book.get_or_insert("bench").cartesian = Some([3000, 3000, 800]);
    book.get_or_insert(&long).cartesian = Some([5000, -1205, 2500]);
    let tool = book.get_or_insert("tool");
    tool.cartesian = Some([-4567, 1234, 10]);
    tool.anchor = true;
    tool.parent = Some(long.clone());
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    let name = long.clone();
    app.handle(Input::Arm(ArmEvent::UnknownPosition { name }), t0);
    press(&mut app, "pagedown", t0);
    assert_eq!(app.selected_name(), Some(long.as_str()));
    (app, t0)
}

fn draw(app: &App, width: u16, height: u16, panel: bool) -> Terminal<TestBackend> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    let view = View::new(app);
    let theme = Theme { color: true };
    terminal
        .draw(|f| {
            if panel {
                ui::positions::draw(f, f.area(), &view, &theme);
            } else {
                ui::dialog::draw(f, f.area(), &view, &theme);
            }
        })
        .expect("draw");
    terminal
}

fn rows(terminal: &Terminal<TestBackend>) -> Vec<String> {
    let buffer = terminal.backend().buffer();
    let width = usize::from(buffer.area.width);
    buffer
        .content
        .chunks(width)
        .map(|row| row.iter().map(|c| c.symbol()).collect())
        .collect()
}

#[test]
fn positions_with_a_300_character_name_keep_their_coordinates_in_view() {
    let (app, _) = app_with_long_names();
    for width in [40, 50, 80] {
        let terminal = draw(&app, width, 6, true);
        let screen = rows(&terminal);
        for coordinates in ["300 300 80 mm", "500 -120 250 mm", "-457 123 1 mm"] {
            assert!(
                screen.iter().any(|row| row.contains(coordinates)),
                "{width} columns: {coordinates} cut:\n{}",
                screen.join("\n")
            );
        }
        assert!(
            screen
                .iter()
                .any(|row| row.contains("> long-0") && row.contains('…')),
            "{width} columns: the long name elided:\n{}",
            screen.join("\n")
        );
    }
    insta::assert_snapshot!(draw(&app, 50, 6, true).backend());
}

#[test]
fn a_form_with_a_300_character_name_shows_its_end_and_refuses_it_with_the_limit() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "p", t0);
    for c in long_name().chars() {
        press(&mut app, &c.to_string(), t0);
    }
    assert!(press(&mut app, "enter", t0).is_empty(), "nothing sent");
    let Overlay::Form(form) = app.overlay() else {
        panic!("the form closed")
    };
    assert_eq!(form.fields[0].value, long_name(), "nothing cut");
    let error = form.error.clone().unwrap_or_default();
    assert!(
        error.contains("300 bytes") && error.contains("at most 255"),
        "{error}"
    );
    insta::assert_snapshot!(draw(&app, 80, 10, false).backend());
}

#[test]
fn a_form_with_a_name_in_wide_characters_keeps_inside_its_border() {
    let (mut app, t0) = app(ReleaseMode::Reported, true);
    press(&mut app, "p", t0);
    // 60 characters two columns wide: 120 columns, wider than the whole screen.
    let name = "位置".repeat(30);
    for c in name.chars() {
        press(&mut app, &c.to_string(), t0);
    }
    let Overlay::Form(form) = app.overlay() else {
        panic!("the form closed")
    };
    assert_eq!(form.fields[0].value, name, "nothing cut");
    let terminal = draw(&app, 80, 10, false);
    let buffer = terminal.backend().buffer();
    let row = |y: u16| -> Vec<String> {
        (0..80)
            .map(|x| buffer[(x, y)].symbol().to_string())
            .collect()
    };
    // The dialog's right edge, from its top border.
    let right = (0..10)
        .find_map(|y| row(y).iter().rposition(|s| s == "┐"))
        .expect("a dialog");
    let field = (0..10)
        .find(|y| row(*y).iter().any(|s| s == "置"))
        .expect("the name's row");
    let cells = row(field);
    assert_eq!(cells[right], "│", "{}", cells.concat());
    // Cut at its start with a `…`, the typing end and its cursor in view.
    // (The cell after a wide character holds a space in the test backend.)
    let text = cells.concat().replace(' ', "");
    assert!(text.contains("…") && text.contains("置_"), "{text}");
}
