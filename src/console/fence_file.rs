//! Writing an arm's fence into its profile in `config.toml` (`[arms.NAME.fence]`), for the console
//! to call when a technician teaches one. The document is edited, not written afresh: comments,
//! order and spacing stay, and only the values that changed are written (a file that would not
//! change is not written). The file is replaced atomically (a temporary file beside it, renamed
//! over it): an error leaves it as it was, but for one after the rename, when the folder's entry
//! could not be flushed. A symlinked file stays a link: the file it points to is replaced.
//!
//! What the fence table holds after a write, the same way every time:
//! - `tool_radius` and `slow_zone`, always (at their defaults too: the numbers to tune are there);
//! - `inside`, `joints` (the joints the fence limits) and the `keep_out` zones when the fence has
//!   them; removed when it has not;
//! - `singularity`, and a zone's `enabled`, when not at their defaults (κ 17/30, `true`); at the
//!   default they are not added, and where the file already writes them they stay, set to it;
//! - a key the fence does not know is left alone (the profile's reader refuses it anyway).
//!
//! A value the file already writes as the fence's number stays as written (`40.0` stays `40.0`).
//! A new one is an integer when whole (`-600`), else a float to a tenth (`12.5`): a tenth of a mm
//! or degree is the arm's precision, and the fence is checked as it will be written.
//!
//! Zones are matched by name: a zone kept keeps its table, its comments and its place (in the
//! fence's order among the places the kept zones had); a zone the fence no longer has is removed,
//! its comments with it; a new zone goes after the one before it in the fence, in the form the
//! file uses (`[[...keep_out]]` tables, or inline tables in an array).
//!
//! A missing file is created with its folder; a missing `[arms.NAME]` is added after everything
//! the file has but the comments that end it (a profile with no other key runs on the built-in
//! simulator); a new `[arms.NAME.fence]` follows its arm's table. The layer above `console` is not
//! used: the limit is the profile reader's own, copied.

use std::io::Write;
use std::path::{Path, PathBuf};

mod merge;

use merge::place;

use crate::link::fence::{Aabb, Fence, FenceError, KeepOut, Singularity};

/// The largest config file read or written: the profile reader's limit
/// (`cli::profiles::file::CONFIG_LIMIT`), so that what is written loads again.
pub const CONFIG_LIMIT: u64 = 1024 * 1024;

/// One arm's fence, to be written into the profiles file.
#[derive(Debug, Clone, PartialEq)]
pub struct FenceSave {
    /// The profiles file (`config.toml`).
    pub file: PathBuf,
    /// The profile: `[arms.NAME]`.
    pub arm: String,
    pub fence: Fence,
    /// The settings a profile made by this write gets (`talos`, `modbus`, ...: the console's
    /// link options, as their options' text); nothing is added to a profile that exists.
    pub new_profile: Vec<(String, String)>,
}

/// Why a fence was not saved. Each names the file; the file is as it was.
#[derive(Debug, thiserror::Error)]
pub enum FenceWriteError {
    /// The fence cannot be kept: the profile would not load.
    #[error(
        "{}: fence not saved: arms.{arm}.fence.{source}{}",
        path.display(),
        if *rounded { " (to a tenth, as it would be written)" } else { "" }
    )]
    Invalid {
        path: PathBuf,
        arm: String,
        source: FenceError,
        /// Only the values rounded to a tenth are wrong.
        rounded: bool,
    },
    #[error("{}: fence not saved: cannot read the file: {source}", path.display())]
    Unreadable {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{}: fence not saved: the file is not valid TOML (fix it first): {message}",
        located(path, *line)
    )]
    NotToml {
        path: PathBuf,
        line: Option<usize>,
        message: String,
    },
    /// `arms`, `arms.NAME` or `arms.NAME.fence` holds something else than a table.
    #[error(
        "{}: fence not saved: {key} is {found}, not a table",
        located(path, *line)
    )]
    NotATable {
        path: PathBuf,
        line: Option<usize>,
        key: String,
        found: &'static str,
    },
    #[error(
        "{}: fence not saved: the file would be {bytes} bytes, over the {limit} bytes armjog reads",
        path.display()
    )]
    TooLarge {
        path: PathBuf,
        bytes: usize,
        limit: u64,
    },
    #[error(
        "{}: fence not saved: cannot make its folder {}: {source}",
        path.display(),
        dir.display()
    )]
    NoFolder {
        path: PathBuf,
        dir: PathBuf,
        source: std::io::Error,
    },
    #[error("{}: fence not saved: cannot write the file: {source}", path.display())]
    Unwritable {
        path: PathBuf,
        source: std::io::Error,
    },
}

/// `config.toml:3`, or `config.toml` when the line is not known.
fn located(path: &Path, line: Option<usize>) -> String {
    match line {
        Some(line) => format!("{}:{line}", path.display()),
        None => path.display().to_string(),
    }
}

/// Writes `save.fence` as `save.arm`'s fence into `save.file`, keeping the rest of the file as it
/// is (see the module's notes). Nothing is written when the file would not change.
pub fn write_fence(save: &FenceSave) -> Result<(), FenceWriteError> {
    let shown = save.file.as_path();
    check(save)?;
    let target = real_path(shown);
    let old = match crate::files::read_to_string_bounded(&target, CONFIG_LIMIT) {
        Ok(text) => Some(text),
        // No file yet; a file where its folder should be is named when the folder is made.
        Err(e)
            if matches!(
                e.kind(),
                std::io::ErrorKind::NotFound | std::io::ErrorKind::NotADirectory
            ) =>
        {
            None
        }
        Err(source) => {
            return Err(FenceWriteError::Unreadable {
                path: shown.to_path_buf(),
                source,
            });
        }
    };
    let text = edit(shown, old.as_deref().unwrap_or(""), save)?;
    if old.as_deref() == Some(text.as_str()) {
        return Ok(());
    }
    if text.len() as u64 > CONFIG_LIMIT {
        return Err(FenceWriteError::TooLarge {
            path: shown.to_path_buf(),
            bytes: text.len(),
            limit: CONFIG_LIMIT,
        });
    }
    replace(shown, &target, &text)
}

/// The fence as given and as written (to a tenth) must both be usable.
fn check(save: &FenceSave) -> Result<(), FenceWriteError> {
    let invalid = |source, rounded| FenceWriteError::Invalid {
        path: save.file.clone(),
        arm: save.arm.clone(),
        source,
        rounded,
    };
    save.fence.check().map_err(|e| invalid(e, false))?;
    as_written(&save.fence)
        .check()
        .map_err(|e| invalid(e, true))
}

/// The fence with every number as a new value is written: to a tenth.
fn as_written(fence: &Fence) -> Fence {
    let corner = |c: [f64; 3]| c.map(tenth);
    let aabb = |b: &Aabb| Aabb {
        min: corner(b.min),
        max: corner(b.max),
    };
    Fence {
        inside: fence.inside.as_ref().map(aabb),
        tool_radius: tenth(fence.tool_radius),
        slow_zone: tenth(fence.slow_zone),
        joints: fence.joints.map(|j| j.map(|l| l.map(tenth))),
        singularity: Singularity {
            slow: tenth(fence.singularity.slow),
            stop: tenth(fence.singularity.stop),
        },
        keep_out: fence
            .keep_out
            .iter()
            .map(|z| KeepOut {
                name: z.name.clone(),
                zone: aabb(&z.zone),
                enabled: z.enabled,
            })
            .collect(),
    }
}

/// `value` to the nearest tenth (`-0` as `0`); a value too large to round, as it is.
pub(super) fn tenth(value: f64) -> f64 {
    let rounded = (value * 10.0).round() / 10.0;
    if !rounded.is_finite() {
        value
    } else if rounded == 0.0 {
        0.0
    } else {
        rounded
    }
}

/// The file a symlinked `config.toml` points to, so that a link (into a dotfiles folder, say)
/// stays a link and its target is what is replaced.
fn real_path(path: &Path) -> PathBuf {
    match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_symlink() => {
            std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf())
        }
        _ => path.to_path_buf(),
    }
}

/// `text` (the file at `shown`) with `arm`'s fence set to `fence`.
fn edit(shown: &Path, text: &str, save: &FenceSave) -> Result<String, FenceWriteError> {
    let parsed = toml_edit::Document::parse(text).map_err(|e| FenceWriteError::NotToml {
        path: shown.to_path_buf(),
        line: e.span().map(|span| line_of(text, span.start)),
        message: one_line(e.message()),
    })?;
    let mut document = parsed.into_mut();
    place(&mut document, &save.arm, &save.fence, &save.new_profile).map_err(|wrong| {
        FenceWriteError::NotATable {
            path: shown.to_path_buf(),
            line: line_of_key(text, &wrong.path),
            key: wrong.path.join("."),
            found: wrong.found,
        }
    })?;
    Ok(document.to_string())
}

/// The 1-based line of byte `at` in `text`.
fn line_of(text: &str, at: usize) -> usize {
    let end = at.min(text.len());
    text.as_bytes()[..end]
        .iter()
        .filter(|b| **b == b'\n')
        .count()
        + 1
}

/// The line of the value at the dotted `path` (`arms`, `cell3`), if the text has it.
fn line_of_key(text: &str, path: &[String]) -> Option<usize> {
    let document = toml_edit::Document::parse(text).ok()?;
    let mut item = document.as_item();
    for key in path {
        item = item.as_table_like()?.get(key)?;
    }
    item.span().map(|span| line_of(text, span.start))
}

/// A TOML message on one line: the parser's may span several.
fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Writes `text` over `target` (named `shown` in errors) atomically: a temporary file beside it,
/// flushed, renamed over it, then the folder flushed so the rename survives a power cut. The
/// file keeps its permissions; a new one is 0644 less the umask. On failure the temporary file
/// is removed and the file is as it was.
fn replace(shown: &Path, target: &Path, text: &str) -> Result<(), FenceWriteError> {
    let unwritable = |source| FenceWriteError::Unwritable {
        path: shown.to_path_buf(),
        source,
    };
    let dir = match target.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) => {
            std::fs::create_dir_all(dir).map_err(|source| FenceWriteError::NoFolder {
                path: shown.to_path_buf(),
                dir: dir.to_path_buf(),
                source,
            })?;
            dir
        }
        None => Path::new("."),
    };
    let mut tmp = crate::files::temp_beside(dir, target).map_err(unwritable)?;
    tmp.write_all(text.as_bytes()).map_err(unwritable)?;
    tmp.as_file().sync_all().map_err(unwritable)?;
    tmp.persist(target).map_err(|e| unwritable(e.error))?;
    crate::files::sync_directory(dir).map_err(unwritable)
}
