//! The console's terminal reader on a socket pair standing in for the terminal: everything
//! readable is drained on each wake, so a STOP after a big paste or a flood is handled at once,
//! and neither is kept in memory.

use std::io::Write;
use std::os::unix::net::UnixStream;
use std::time::{Duration, Instant};

use armjog::console::input::{Refusal, TerminalEvent, TerminalInput};
use crossterm::event::{Event, KeyCode};
use futures::StreamExt;

/// Generous for a loaded 2-core CI: the drain itself takes a few ms.
const STOP_WITHIN: Duration = Duration::from_millis(500);

fn terminal() -> (UnixStream, TerminalInput) {
    let (typist, console) = UnixStream::pair().expect("socket pair");
    console.set_nonblocking(true).expect("non-blocking");
    (typist, TerminalInput::new(console.into()).expect("reader"))
}

fn is_space(event: &TerminalEvent) -> bool {
    matches!(event, TerminalEvent::Event(Event::Key(k)) if k.code == KeyCode::Char(' '))
}

/// Events up to and including the first space, and when that came.
async fn until_space(input: &mut TerminalInput) -> (Vec<TerminalEvent>, Instant) {
    let mut events = Vec::new();
    loop {
        let event = tokio::time::timeout(Duration::from_secs(20), input.next())
            .await
            .expect("the space came")
            .expect("input open")
            .expect("read");
        let space = is_space(&event);
        events.push(event);
        if space {
            return (events, Instant::now());
        }
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stop_after_a_1_mb_paste_is_handled_at_once_and_the_paste_is_refused() {
    let (mut typist, mut input) = terminal();
    let writer = std::thread::spawn(move || {
        let mut paste = b"\x1b[200~".to_vec();
        paste.extend(std::iter::repeat_n(b'h', 1024 * 1024));
        paste.extend(b"\x1b[201~");
        typist.write_all(&paste).expect("paste");
        let stop_typed = Instant::now();
        typist.write_all(b" ").expect("stop");
        (typist, stop_typed)
    });
    let (events, handled) = until_space(&mut input).await;
    let (_typist, typed) = writer.join().expect("writer");
    let latency = handled.saturating_duration_since(typed);
    println!("STOP after a 1 MiB paste: {latency:?}");
    assert!(latency < STOP_WITHIN, "{latency:?}");
    assert_eq!(
        events,
        [
            TerminalEvent::Refused(Refusal::PasteTooLong { bytes: 1024 * 1024 }),
            TerminalEvent::Event(Event::Key(KeyCode::Char(' ').into())),
        ],
        "the paste is one refusal, and no key"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_flood_of_keys_is_dropped_with_one_refusal_and_a_stop_after_a_pause_is_a_key() {
    let (mut typist, mut input) = terminal();
    let writer = std::thread::spawn(move || {
        // 1 MiB of "why", as a terminal without bracketed paste sends a paste.
        let flood: Vec<u8> = b"why".iter().copied().cycle().take(1024 * 1024).collect();
        typist.write_all(&flood).expect("flood");
        std::thread::sleep(Duration::from_millis(500));
        let stop_typed = Instant::now();
        typist.write_all(b" ").expect("stop");
        (typist, stop_typed)
    });
    let (events, handled) = until_space(&mut input).await;
    let (_typist, typed) = writer.join().expect("writer");
    let latency = handled.saturating_duration_since(typed);
    println!("STOP after a 1 MiB flood: {latency:?}");
    assert!(latency < STOP_WITHIN, "{latency:?}");
    let refusals = events
        .iter()
        .filter(|e| **e == TerminalEvent::Refused(Refusal::Flood))
        .count();
    let keys = events.len() - refusals - 1;
    assert_eq!(refusals, 1, "one message");
    assert!(
        keys <= 4096,
        "{keys} keys of the flood got through, more than its first 4 KiB"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_closed_terminal_ends_the_stream() {
    let (typist, mut input) = terminal();
    drop(typist);
    let end = tokio::time::timeout(Duration::from_secs(5), input.next()).await;
    assert!(matches!(end, Ok(None)), "{end:?}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn input_that_has_arrived_is_told_until_the_event_loop_takes_it() {
    let (mut typist, mut input) = terminal();
    assert!(!input.input_arrived(), "nothing typed");
    typist.write_all(b" ").expect("space");
    // The thread reads it, then hands it over: from the read until it is taken, it is told.
    let until = Instant::now() + Duration::from_secs(20);
    while !input.input_arrived() {
        assert!(Instant::now() < until, "the space was told within 20 s");
        tokio::time::sleep(Duration::from_millis(1)).await;
    }
    let event = tokio::time::timeout(Duration::from_secs(20), input.next())
        .await
        .expect("the space came")
        .expect("input open")
        .expect("read");
    assert!(is_space(&event), "{event:?}");
    assert!(!input.input_arrived(), "taken: nothing more has arrived");
}

#[tokio::test]
async fn a_jog_keys_release_is_handed_on_as_a_release_and_one_inside_a_paste_is_text() {
    use crossterm::event::KeyEventKind;
    let (mut typist, mut input) = terminal();
    // The release of "w" (+X) in the kitty protocol: the app stops the arm on it.
    typist.write_all(b"\x1b[119;1:3u").expect("w released");
    let event = input.next().await.expect("open").expect("read");
    assert!(
        matches!(&event, TerminalEvent::Event(Event::Key(k))
            if k.code == KeyCode::Char('w') && k.kind == KeyEventKind::Release),
        "{event:?}"
    );
    // A paste is text: the release's bytes inside one are no key.
    typist
        .write_all(b"\x1b[200~\x1b[119;1:3u\x1b[201~")
        .expect("paste");
    let event = input.next().await.expect("open").expect("read");
    assert!(matches!(event, TerminalEvent::Paste(_)), "{event:?}");
}
