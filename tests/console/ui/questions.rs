//! The yes/no questions at every size the console draws: the answers always show, under a
//! question cut to fit; a long list (a 10,000-leg tour's) shows the things that fit and ends
//! `… and N more`.

use armjog::console::app::{App, Input, MIN_HEIGHT, MIN_WIDTH, Overlay};
use armjog::console::form::{Confirm, Form, FormKind, FormResult, TourQuestion};
use armjog::console::jog::ReleaseMode;
use armjog::console::positions::{PositionBook, Tour};
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::{Stored, StoredMotion};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

use crate::app_support;

/// A tour of `legs` legs, `p0` to `p…`.
fn tour(legs: usize) -> Confirm {
    Confirm::Tour(TourQuestion {
        tour: Tour {
            name: "rounds".into(),
            positions: (0..legs).map(|i| format!("p{i}")).collect(),
        },
        one_leg: false,
    })
}

/// A name of 255 characters, the longest the name rule lets through.
fn longest_name() -> String {
    "n".repeat(255)
}

/// Every question the console asks, those naming a position with the longest name.
fn every_question() -> Vec<Confirm> {
    let name = longest_name();
    let overwritten = FormResult::Save {
        name: name.clone(),
        anchor: false,
        parent: None,
    };
    vec![
        tour(10_000),
        Confirm::Home,
        Confirm::GoTo(name.clone()),
        Confirm::Delete {
            name: name.clone(),
            tours: (0..10_000).map(|i| format!("{name}{i}")).collect(),
        },
        Confirm::Resave(name.clone()),
        Confirm::Overwrite {
            result: overwritten,
            form: Box::new(Form::new(FormKind::Save, &name)),
        },
        Confirm::QuitUnsaved { count: 10_000 },
        Confirm::Stored(Stored {
            motion: StoredMotion::Sequence,
            id: 65_535,
        }),
    ]
}

/// The whole screen at `width` x `height` with `question` open, a row a line; only the dialog
/// when `whole` is false (as fast, drawn on the same area).
fn screen(view: &View, width: u16, height: u16, whole: bool) -> Vec<String> {
    let mut terminal = Terminal::new(TestBackend::new(width, height)).expect("terminal");
    let theme = Theme { color: false };
    terminal
        .draw(|f| {
            if whole {
                ui::draw(f, view, &theme)
            } else {
                ui::dialog::draw(f, f.area(), view, &theme)
            }
        })
        .expect("draw");
    let buffer = terminal.backend().buffer();
    (0..height)
        .map(|y| (0..width).map(|x| buffer[(x, y)].symbol()).collect())
        .collect()
}

/// The dialog's rows, inside its borders, trimmed.
fn dialog_rows(rows: &[String]) -> Vec<String> {
    let grid: Vec<Vec<char>> = rows.iter().map(|row| row.chars().collect()).collect();
    let (top, left) = rows
        .iter()
        .enumerate()
        .find_map(|(y, row)| {
            let at = row.find("┌ Confirm ")?;
            Some((y, row[..at].chars().count()))
        })
        .expect("the dialog's top border");
    let right = (left + 1..grid[top].len())
        .find(|&x| grid[top][x] == '┐')
        .expect("the dialog's top right corner");
    grid[top + 1..]
        .iter()
        .take_while(|row| row[left] != '└')
        .map(|row| {
            let inside: String = row[left + 1..right].iter().collect();
            inside.trim_end().to_string()
        })
        .collect()
}

/// A question named for a failure: a tour by its length, not its 10,000 legs.
fn named(question: &Confirm) -> String {
    match question {
        Confirm::Tour(tour) => format!("a tour of {} legs", tour.tour.positions.len()),
        other => format!("{other:?}").chars().take(60).collect(),
    }
}

/// The view of `app` with `question` open.
fn asking(app: &App, question: &Confirm) -> View {
    let mut view = View::new(app);
    view.screen.overlay = Overlay::Confirm(question.clone());
    view
}

/// Sizes from the smallest the console draws up: every width to a little past the dialog's
/// widest (72 columns), every height to 24 rows, then larger ones.
fn sizes() -> Vec<(u16, u16)> {
    let widths = (MIN_WIDTH..=74).chain([120, 250]);
    let heights: Vec<u16> = (MIN_HEIGHT..=24).chain([40, 60]).collect();
    widths
        .flat_map(|w| heights.iter().map(move |h| (w, *h)))
        .collect()
}

#[test]
fn every_questions_answers_show_at_every_size() {
    let (app, _) = app_support::app(ReleaseMode::Reported, false);
    for question in every_question() {
        let view = asking(&app, &question);
        // The answers as they wrap at the narrowest dialog: each of their words shows.
        let answers: Vec<&str> = question.answers().split_whitespace().collect();
        for (width, height) in sizes() {
            let rows = dialog_rows(&screen(&view, width, height, false));
            let last = rows.last().cloned().unwrap_or_default();
            let shown = rows.join(" ");
            for word in &answers {
                assert!(
                    shown.contains(word),
                    "{width}x{height} {}: '{word}' missing from {rows:#?}",
                    named(&question)
                );
            }
            assert!(
                answers.iter().any(|word| last.contains(word)),
                "{width}x{height}: the answers are not the last row: {rows:#?}"
            );
            // The question starts on the first row, and no row is past the border.
            assert!(!rows[0].is_empty(), "{width}x{height}: {rows:#?}");
        }
    }
}

#[test]
fn a_10000_leg_tours_question_lists_the_legs_that_fit_and_counts_the_rest() {
    let (app, _) = app_support::app(ReleaseMode::Reported, false);
    let view = asking(&app, &tour(10_000));
    for (width, height) in sizes() {
        let rows = dialog_rows(&screen(&view, width, height, false));
        let text = rows.join(" ");
        assert!(
            text.starts_with("Play tour 'rounds' straight through, 10000 legs: p0"),
            "{width}x{height}: {rows:#?}"
        );
        // The legs shown are the first ones, in order, and the count is of the rest.
        let listed = text
            .split(": ")
            .nth(1)
            .and_then(|rest| rest.split(" … and ").next())
            .unwrap_or_default();
        let shown = listed.split(" → ").count();
        assert!(
            text.contains(&format!("… and {} more?", 10_000 - shown)),
            "{width}x{height}: {shown} shown: {rows:#?}"
        );
        let last_shown = format!("p{}", shown - 1);
        assert!(
            listed.trim_end().ends_with(&last_shown),
            "{width}x{height}: {listed}"
        );
        assert!(
            text.contains("y or enter: yes"),
            "{width}x{height}: {rows:#?}"
        );
    }
    let smallest = screen(&view, MIN_WIDTH, MIN_HEIGHT, true).join("\n");
    insta::assert_snapshot!("tour_of_10000_legs_40x10", smallest);
    let usual = screen(&view, 80, 24, true).join("\n");
    insta::assert_snapshot!("tour_of_10000_legs_80x24", usual);
}

#[test]
fn a_short_tours_question_lists_every_leg() {
    let (app, _) = app_support::app(ReleaseMode::Reported, false);
    let rows = dialog_rows(&screen(&asking(&app, &tour(3)), 80, 24, true));
    assert_eq!(
        rows,
        [
            "Play tour 'rounds' straight through, 3 legs: p0 → p1 → p2?",
            "",
            "y or enter: yes    any other key: no"
        ]
    );
}

#[test]
fn a_long_name_is_cut_where_it_does_not_fit_and_the_answers_stay() {
    let (app, _) = app_support::app(ReleaseMode::Reported, false);
    let view = asking(
        &app,
        &Confirm::Delete {
            name: longest_name(),
            tours: Vec::new(),
        },
    );
    let rows = dialog_rows(&screen(&view, MIN_WIDTH, MIN_HEIGHT, true));
    insta::assert_snapshot!("delete_with_the_longest_name_40x10", rows.join("\n"));
    assert!(rows[rows.len() - 3].ends_with('…'), "{rows:#?}");
    assert_eq!(rows[rows.len() - 1], "y or enter: yes    any other key: no");
}

#[test]
fn an_unknown_tours_name_lists_the_first_tours_and_counts_the_rest() {
    let (mut app, t0) = app_support::app(ReleaseMode::Reported, false);
    let mut book = PositionBook::new();
    book.get_or_insert("bench").cartesian = Some([4000, 0, 3000]);
    for i in 0..30 {
        book.set_tour(Tour {
            name: format!("t{i}"),
            positions: vec!["bench".into()],
        });
    }
    app.handle(Input::PositionsLoaded(Ok(book)), t0);
    app.handle(
        Input::Resize {
            width: MIN_WIDTH,
            height: MIN_HEIGHT,
        },
        t0,
    );
    app_support::press(&mut app, "O", t0);
    for _ in 0.."t0".len() {
        app_support::press(&mut app, "backspace", t0);
    }
    for c in "nope".chars() {
        app_support::press(&mut app, &c.to_string(), t0);
    }
    app_support::press(&mut app, "enter", t0);
    let Overlay::Form(form) = app.overlay() else {
        panic!("the form stays open: {:?}", app.overlay())
    };
    assert_eq!(
        form.error.as_deref(),
        Some("no tour 'nope'; the book has: t0, t1, t2, t3, t4, t5, t6, t7 … and 22 more")
    );
    // At the smallest size the form's keys still show under the error.
    let mut terminal = Terminal::new(TestBackend::new(MIN_WIDTH, MIN_HEIGHT)).expect("terminal");
    let view = View::new(&app);
    terminal
        .draw(|f| ui::draw(f, &view, &Theme { color: false }))
        .expect("draw");
    let text = app_support::buffer_text(terminal.backend().buffer());
    assert!(text.contains("enter: ok"), "{text}");
    assert!(text.contains("cancel"), "{text}");
    assert!(text.contains("no tour 'nope'"), "{text}");
}
