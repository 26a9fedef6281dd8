//! The terminal the console owns: set up, probe for key-release support, and always restored.

use std::io::{Write, stdout};

use crossterm::event::{
    DisableBracketedPaste, DisableFocusChange, EnableBracketedPaste, EnableFocusChange,
    KeyboardEnhancementFlags, PopKeyboardEnhancementFlags, PushKeyboardEnhancementFlags,
};
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use crossterm::{cursor, execute};

/// Raw mode on the alternate screen with focus reports and bracketed paste (a paste is text, never
/// keys). Returns whether key releases are reported (kitty protocol, then switched on); no answer
/// to the probe means no.
pub fn enter(force_release_events: Option<bool>) -> std::io::Result<bool> {
    enable_raw_mode()?;
    let mut out = stdout();
    execute!(
        out,
        EnterAlternateScreen,
        EnableFocusChange,
        EnableBracketedPaste,
        cursor::Hide
    )?;
    let supported = match force_release_events {
        Some(forced) => forced,
        None => crossterm::terminal::supports_keyboard_enhancement().unwrap_or(false),
    };
    if supported {
        execute!(
            out,
            PushKeyboardEnhancementFlags(
                KeyboardEnhancementFlags::REPORT_EVENT_TYPES
                    | KeyboardEnhancementFlags::REPORT_ALL_KEYS_AS_ESCAPE_CODES
                    | KeyboardEnhancementFlags::DISAMBIGUATE_ESCAPE_CODES
                    // Shifted symbols arrive as themselves ('?' rather than shift+'/').
                    | KeyboardEnhancementFlags::REPORT_ALTERNATE_KEYS
            )
        )?;
    }
    Ok(supported)
}

/// Gives the terminal back; safe to repeat and from the panic hook; errors ignored on the way out.
pub fn restore(release_events: bool) {
    let mut out = stdout();
    if release_events {
        let _ = execute!(out, PopKeyboardEnhancementFlags);
    }
    let _ = execute!(
        out,
        DisableBracketedPaste,
        DisableFocusChange,
        LeaveAlternateScreen,
        cursor::Show
    );
    let _ = disable_raw_mode();
    let _ = out.flush();
}
