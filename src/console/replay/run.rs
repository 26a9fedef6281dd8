//! The terminal's end of playback: the player's view drawn with the console's panels, the
//! technician's keys given to the player (never to an arm: no link is opened), the time that
//! passed handed to it. One thread; a frame at most every [`FRAME`].

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossterm::event::{self, Event, KeyEventKind};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

use super::{Control, Player, Recording};
use crate::console::app::KeyInput;
use crate::console::jog::KeyKind;
use crate::console::keymap::KeyName;
use crate::console::terminal;
use crate::console::ui::{self, Theme};

/// The time between frames while playing.
const FRAME: Duration = Duration::from_millis(33);

/// Plays `path` until the technician quits. `Err`: why the file cannot be played, or the
/// terminal failed.
/// `quit` set (a signal): it ends as `q` does.
pub fn run(path: &Path, quit: &AtomicBool) -> Result<(), String> {
    let recording = Recording::read(path).map_err(|e| e.to_string())?;
    let release_events = terminal::enter(Some(false)).map_err(|e| format!("terminal: {e}"))?;
    // A panic gives the terminal back before it reports.
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        terminal::restore(release_events);
        previous(info);
    }));
    let played = play(recording, quit);
    terminal::restore(release_events);
    let _ = std::panic::take_hook();
    played.map_err(|e| format!("terminal: {e}"))
}

fn play(recording: Recording, quit: &AtomicBool) -> std::io::Result<()> {
    // Never dropped, as the console's: its drop `eprintln!`s when the terminal has hung up.
    let mut terminal =
        std::mem::ManuallyDrop::new(Terminal::new(CrosstermBackend::new(std::io::stdout()))?);
    let size = terminal.size()?;
    let theme = Theme::from_env();
    let mut player = Player::new(recording, (size.width, size.height), Instant::now());
    let mut last = Instant::now();
    let mut drawn = None;
    while !quit.load(Ordering::Relaxed) {
        let view = player.view();
        if drawn.as_ref() != Some(&view) {
            terminal.draw(|frame| ui::draw(frame, &view, &theme))?;
            drawn = Some(view);
        }
        if event::poll(FRAME)? {
            match event::read()? {
                Event::Key(key) if key.kind != KeyEventKind::Release => {
                    let Some(name) = KeyName::from_event(&key) else {
                        continue;
                    };
                    let input = KeyInput {
                        key: name,
                        text: None,
                        kind: KeyKind::Press,
                    };
                    if player.on_key(&input) == Control::Quit {
                        return Ok(());
                    }
                }
                Event::Resize(width, height) => {
                    player.on_resize(width, height);
                    terminal.autoresize()?;
                }
                _ => {}
            }
        }
        let now = Instant::now();
        player.play(now - last);
        last = now;
    }
    Ok(())
}
