//! The real `armjog` binary in tmux, as a technician sees it (`.ci/run` installs tmux).

mod logs;
mod paste;
mod profile;
mod session;
mod shared_book;
