//! What a one-shot command (`send`, `status`, `modbus`) prints and how it exits.

/// A one-shot command's output lines, its error line and its exit status.
pub struct Outcome {
    pub stdout: Vec<String>,
    pub stderr: Option<String>,
    pub exit_code: i32,
}
