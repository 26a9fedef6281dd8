//! The reader itself: a file built by hand from the spec reads as written; a recording with any
//! byte changed is refused (the CRCs); with the CRCs zeroed ("not available"), a Statistics,
//! Chunk Index, Message Index or Chunk that says what is not so is still refused.

use std::time::Duration;

use armjog::console::app::{Input, KeyInput, Severity};
use armjog::console::jog::{JogMotion, KeyKind};
use armjog::console::recorder::{QUEUE, Recorder};
use armjog::link::driver::hw_telemetry;
use armjog::link::interface::{ArmCommand, ArmEvent, LinkStatus};
use armjog::sim::arm_model::Arm;
use armjog::sim::telemetry::{actuator_feedback, arm_state};

use super::records::{self, MAGIC};

fn string(s: &str) -> Vec<u8> {
    let mut out = (s.len() as u32).to_le_bytes().to_vec();
    out.extend(s.as_bytes());
    out
}

fn record(opcode: u8, content: &[u8]) -> Vec<u8> {
    let mut out = vec![opcode];
    out.extend((content.len() as u64).to_le_bytes());
    out.extend(content);
    out
}

/// The spec's "Single Message" diagram, by hand: Header, Schema, Channel, Message, Footer.
fn single_message(message_first: bool) -> Vec<u8> {
    let header = [string(""), string("by hand")].concat();
    let schema_json = br#"{"type":"object"}"#;
    let schema = [
        1u16.to_le_bytes().to_vec(),
        string("hand.Thing"),
        string("jsonschema"),
        (schema_json.len() as u32).to_le_bytes().to_vec(),
        schema_json.to_vec(),
    ]
    .concat();
    let channel = [
        7u16.to_le_bytes().to_vec(),
        1u16.to_le_bytes().to_vec(),
        string("/thing"),
        string("json"),
        0u32.to_le_bytes().to_vec(),
    ]
    .concat();
    let message = [
        &7u16.to_le_bytes()[..],
        &3u32.to_le_bytes(),
        &5u64.to_le_bytes(),
        &6u64.to_le_bytes(),
        b"{\"a\":1}",
    ]
    .concat();
    let mut body = vec![record(records::SCHEMA, &schema)];
    if message_first {
        body.push(record(records::MESSAGE, &message));
        body.push(record(records::CHANNEL, &channel));
    } else {
        body.push(record(records::CHANNEL, &channel));
        body.push(record(records::MESSAGE, &message));
    }
    [
        MAGIC.to_vec(),
        record(records::HEADER, &header),
        body.concat(),
        record(records::FOOTER, &[0; 20]),
        MAGIC.to_vec(),
    ]
    .concat()
}

#[test]
fn a_file_made_by_hand_from_the_spec_reads_as_written() {
    let file = super::read(&single_message(false)).expect("the spec's single message");
    assert_eq!(
        (file.profile.as_str(), file.library.as_str()),
        ("", "by hand")
    );
    let [message] = file.messages.as_slice() else {
        panic!("{} messages", file.messages.len());
    };
    let m = message;
    assert_eq!((m.channel_id, m.sequence, m.log_time), (7, 3, 5));
    assert_eq!((m.publish_time, m.data.as_slice()), (6, &b"{\"a\":1}"[..]));
    let (channel, schema) = file.schema_of(message).expect("its channel and schema");
    assert_eq!(
        (channel.topic.as_str(), channel.message_encoding.as_str()),
        ("/thing", "json")
    );
    assert_eq!(
        (schema.name.as_str(), schema.data.as_slice()),
        ("hand.Thing", &br#"{"type":"object"}"#[..])
    );
    assert_eq!(file.data_section_crc, None);
    assert!(file.summary.is_none() && file.chunks.is_empty());
    let error = super::read(&single_message(true)).err().expect("refused");
    assert!(error.contains("before it"), "{error}");
}

fn telemetry() -> Input {
    let snapshot = Arm::default().snapshot();
    let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
    let telemetry = hw_telemetry::telemetry(&arm_state(&snapshot), &feedback);
    Input::Arm(ArmEvent::Telemetry(Box::new(telemetry)))
}

/// A short recording: link up, telemetry, a key, a jog, a stop, a message line.
fn recorded() -> Vec<u8> {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("short.mcap");
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    let up = LinkStatus::Up {
        description: "test".into(),
    };
    recorder.input(&Input::Arm(ArmEvent::Status(up)));
    recorder.input(&telemetry());
    recorder.input(&Input::Key(KeyInput {
        key: "w".parse().expect("w"),
        text: Some('w'),
        kind: KeyKind::Press,
    }));
    recorder.command(&ArmCommand::Jog(JogMotion::Cartesian { x: 1, y: 0, z: 0 }));
    recorder.hand_over();
    // A second chunk: chunks close each second (half a second's margin for a busy machine).
    std::thread::sleep(Duration::from_millis(1500));
    recorder.command(&ArmCommand::Stop);
    recorder.said(Some(("stopped", Severity::Info)));
    drop(recorder);
    std::fs::read(&path).expect("the recording")
}

#[test]
fn any_byte_of_a_recording_changed_is_caught() {
    let bytes = recorded();
    let file = super::read(&bytes).expect("a good recording");
    assert!(file.chunks.len() >= 2, "{} chunks", file.chunks.len());
    assert!(super::read(&bytes[..bytes.len() - 1]).is_err(), "cut short");
    for at in 0..bytes.len() {
        let mut changed = bytes.clone();
        changed[at] ^= 0x10;
        assert!(
            super::read(&changed).is_err(),
            "byte {at} of {} changed",
            bytes.len()
        );
    }
}

/// The content offset of the first record with `opcode` in `bytes[start..end]`.
fn content_of(bytes: &[u8], start: usize, end: usize, opcode: u8) -> usize {
    let records = records::records(bytes, start, end).expect("records");
    let found = records.iter().find(|r| r.opcode == opcode);
    found.expect("the record").offset + 9
}

fn add(bytes: &mut [u8], at: usize, n: i64) {
    let field: &mut [u8; 8] = (&mut bytes[at..at + 8]).try_into().expect("8 bytes");
    *field = u64::from_le_bytes(*field)
        .wrapping_add_signed(n)
        .to_le_bytes();
}

#[test]
fn without_crcs_what_the_records_say_is_still_checked() {
    let mut bytes = recorded();
    let footer = bytes.len() - MAGIC.len() - 29 + 9;
    let summary = u64::from_le_bytes(bytes[footer..footer + 8].try_into().expect("8")) as usize;
    // The data section's CRC zeroed ("not available"): a changed summary is the summary CRC's.
    let data_end = content_of(&bytes, MAGIC.len(), summary, records::DATA_END);
    bytes[data_end..data_end + 4].fill(0);
    let mut changed = bytes.clone();
    add(
        &mut changed,
        content_of(&bytes, summary, footer - 9, records::STATISTICS),
        1,
    );
    let error = super::read(&changed)
        .err()
        .expect("a changed summary refused");
    assert!(error.contains("summary CRC"), "{error}");
    // Both zeroed: the file still reads.
    bytes[footer + 16..footer + 20].fill(0);
    let file = super::read(&bytes).expect("a file without CRCs");
    assert_eq!(file.data_section_crc, Some(0));
    let statistics = content_of(&bytes, summary, footer - 9, records::STATISTICS);
    let chunk_index = content_of(&bytes, summary, footer - 9, records::CHUNK_INDEX);
    let message_index = content_of(&bytes, MAGIC.len(), summary, records::MESSAGE_INDEX);
    let chunk = content_of(&bytes, MAGIC.len(), summary, records::CHUNK);
    let summary_schema = content_of(&bytes, summary, footer - 9, records::SCHEMA);
    let cases: [(&str, usize, i64, &str); 7] = [
        ("Statistics message_count", statistics, 1, "message_count"),
        ("Chunk uncompressed_crc", chunk + 24, 1, "CRC mismatch"),
        (
            "Statistics message_end_time",
            statistics + 34,
            -1,
            "message_end_time",
        ),
        (
            "Chunk Index chunk_start_offset",
            chunk_index + 16,
            1,
            "no Chunk starts",
        ),
        (
            "Message Index's first offset",
            message_index + 2 + 4 + 8,
            1,
            "Message Indexes",
        ),
        ("Chunk message_end_time", chunk + 8, -1, "its messages"),
        // Its id: the summary's copy is then a schema the data section does not have.
        (
            "summary Schema id",
            summary_schema,
            100,
            "the summary's schema",
        ),
    ];
    for (what, at, n, said) in cases {
        let mut wrong = bytes.clone();
        add(&mut wrong, at, n);
        match super::read(&wrong) {
            Ok(_) => panic!("{what} changed: read all the same"),
            Err(error) => assert!(error.contains(said), "{what}: {error}"),
        }
    }
}
