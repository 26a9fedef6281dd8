//! The status bar during a tour (`TOUR 2/5 → bench`, after the go-to's `MOVING: GOTO bench`)
//! and with the arm profile's name before the link (`arm cell3`).

use armjog::console::keymap::Keymap;
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::app::tours::{Bench, leg};

fn status_rows(bench: &Bench, width: u16) -> String {
    view_rows(&View::new(&bench.app), width)
}

fn view_rows(view: &View, width: u16) -> String {
    let mut terminal = Terminal::new(TestBackend::new(width, 2)).expect("terminal");
    terminal
        .draw(|f| ui::status::draw(f, f.area(), view, &Theme { color: false }))
        .expect("draw");
    let buffer = terminal.backend().buffer();
    (0..2)
        .map(|y| {
            let row: String = (0..width).map(|x| buffer[(x, y)].symbol()).collect();
            row.trim_end().to_string()
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn status_bar_on_a_tour_with_the_profiles_name() {
    let names = ["dock", "bench", "pick", "place", "rest"];
    let mut bench = Bench::with(false, Some("cell3"), &names);
    let first = leg(&bench.play("O"));
    leg(&bench.finish_leg(first));
    let rows = status_rows(&bench, 110);
    assert!(rows.contains(" arm cell3 "), "{rows}");
    assert!(rows.contains("MOVING: GOTO bench"), "{rows}");
    assert!(rows.contains(" TOUR 2/5 → bench "), "{rows}");
    insta::assert_snapshot!("tour_leg_2_of_5_cell3_110", rows);
    // Narrow, the tour keeps its count.
    let narrow = status_rows(&bench, 44);
    assert!(narrow.contains("TOUR 2/5"), "{narrow}");
    insta::assert_snapshot!("tour_leg_2_of_5_cell3_44", narrow);
}

#[test]
fn status_bar_one_leg_at_a_time_waiting_for_the_next_leg() {
    let mut bench = Bench::with(false, None, &["dock", "bench", "pick"]);
    let first = leg(&bench.play("N"));
    bench.finish_leg(first);
    let rows = status_rows(&bench, 110);
    assert!(!rows.contains(" arm "), "no profile, no name: {rows}");
    // The next leg's key, as the keymap in use names it.
    assert!(rows.contains(" TOUR 1/3 at dock: N next leg "), "{rows}");
    insta::assert_snapshot!("tour_waiting_for_leg_2", rows);
    // Keys are remappable: a keymap binding the next leg to f5 names f5.
    let remapped = r#"{ "name": "remapped", "bindings": {
        "space": "stop", "q": "quit", "f5": "tour_leg" } }"#;
    let mut view = View::new(&bench.app);
    view.session.keymap = Keymap::from_json("remapped.json", remapped)
        .expect("keymap")
        .into();
    let rows = view_rows(&view, 110);
    assert!(rows.contains(" TOUR 1/3 at dock: f5 next leg "), "{rows}");
}
