//! IO errors in a technician's words ("connection refused"), never "os error 113".

use std::io;

/// The raw OS error's words, else the kind's, else the text without "(os error N)".
pub fn io_error_words(error: &io::Error) -> String {
    if let Some(words) = error.raw_os_error().and_then(os_error_words) {
        return words.to_string();
    }
    if let Some(words) = kind_words(error.kind()) {
        return words.to_string();
    }
    let text = error.to_string();
    let text = match text.rfind(" (os error ") {
        Some(at) if text.ends_with(')') => text[..at].to_string(),
        _ => text,
    };
    lowercase_first(&text)
}

/// Linux errno values a link meets whose kind ([`kind_words`]) says less or nothing.
#[cfg(target_os = "linux")]
fn os_error_words(code: i32) -> Option<&'static str> {
    Some(match code {
        1 => "operation not permitted (a firewall?)",
        112 => "host is down",
        // EINPROGRESS: a non-blocking connect that had not completed when it was given up.
        114 | 115 => "timed out (the connection was still being set up)",
        _ => return None,
    })
}

#[cfg(not(target_os = "linux"))]
fn os_error_words(_code: i32) -> Option<&'static str> {
    None
}

fn kind_words(kind: io::ErrorKind) -> Option<&'static str> {
    use io::ErrorKind as K;
    Some(match kind {
        K::ConnectionRefused => "connection refused",
        K::ConnectionReset => "connection reset by the peer",
        K::ConnectionAborted => "connection aborted",
        K::NotConnected => "not connected",
        K::HostUnreachable => "no route to host",
        K::NetworkUnreachable => "network unreachable",
        K::NetworkDown => "network is down",
        K::TimedOut => "timed out",
        K::BrokenPipe => "connection closed by the peer (broken pipe)",
        K::UnexpectedEof => "connection closed by the peer",
        K::AddrInUse => "address already in use",
        K::AddrNotAvailable => "address not available",
        K::PermissionDenied => "permission denied",
        _ => return None,
    })
}

fn lowercase_first(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(first) => first.to_lowercase().chain(chars).collect(),
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(target_os = "linux")]
    #[test]
    fn raw_linux_errors_read_as_words() {
        // Written by hand from errno(3): most read as their kind's words.
        for (code, words) in [
            (1, "operation not permitted (a firewall?)"),
            (13, "permission denied"),
            (32, "connection closed by the peer (broken pipe)"),
            (98, "address already in use"),
            (99, "address not available"),
            (100, "network is down"),
            (101, "network unreachable"),
            (103, "connection aborted"),
            (104, "connection reset by the peer"),
            (107, "not connected"),
            (110, "timed out"),
            (111, "connection refused"),
            (112, "host is down"),
            (113, "no route to host"),
        ] {
            assert_eq!(io_error_words(&io::Error::from_raw_os_error(code)), words);
        }
        let in_progress = io_error_words(&io::Error::from_raw_os_error(115));
        assert!(in_progress.starts_with("timed out"), "{in_progress}");
    }

    #[test]
    fn no_os_error_number_is_shown() {
        for code in [2, 5, 22, 111, 113, 115, 9999] {
            let words = io_error_words(&io::Error::from_raw_os_error(code));
            assert!(!words.contains("os error"), "{code}: {words}");
            assert!(!words.is_empty(), "{code}");
        }
    }

    #[test]
    fn kinds_without_a_code_read_as_words() {
        let e = io::Error::new(io::ErrorKind::TimedOut, "deadline");
        assert_eq!(io_error_words(&e), "timed out");
        let e = io::Error::other("the name resolved to no address");
        assert_eq!(io_error_words(&e), "the name resolved to no address");
    }
}
