//! `armjog replay FILE`: a session run on a fake clock (link up, a jog, its stop, a fault, a
//! refused press), recorded as the console records it, then played back. At ×1 the panels show
//! what the console showed live at the same times; the technician's keys move playback, never
//! the arm; a file cut short plays up to its last good message and says so.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use armjog::console::app::{App, AppConfig, Effect, Input, KeyInput};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::console::recorder::{QUEUE, Recorder};
use armjog::console::replay::{Control, Happened, Player, Recording, RecordingError, config_of};
use armjog::console::ui::{self, Theme};
use armjog::console::view::View;
use armjog::kortex::{Coded, Flag, FlagSet, RobotState, Telemetry};
use armjog::link::driver::hw_telemetry;
use armjog::link::interface::{ArmEvent, LinkStatus, LogEntry, TelemetrySource};
use armjog::sim::arm_model::Arm;
use armjog::sim::telemetry::{actuator_feedback, arm_state};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

const WIDTH: u16 = 120;
const HEIGHT: u16 = 40;
/// 2026-12-06T18:03:05Z, ns since the Unix epoch: where the session starts.
const START_NS: u64 = 1_796_580_185_000_000_000;

/// The simulator's arm at home (its own digits, as a live session gets them), `x_mm` along
/// base X and J1 turned by `deg`; in fault when `faulted`.
fn sample(x_mm: f32, deg: f32, moving: bool, faulted: bool) -> Telemetry {
    let snapshot = Arm::default().snapshot();
    let feedback: Vec<_> = (1..=7).map(|j| actuator_feedback(&snapshot, j)).collect();
    let mut t = hw_telemetry::telemetry(&arm_state(&snapshot), &feedback);
    t.tcp.pose.x += x_mm / 1000.0;
    t.joints[0].position += deg;
    if moving {
        t.tcp.twist.x = 0.1;
        t.joints[0].velocity = 2.5;
    }
    if faulted {
        t.robot_state = Coded::Known(RobotState::InFault);
        t.faults = FlagSet::from_bits(1 << (Flag::JointFault as u32));
    }
    t
}

fn key(kind: KeyKind) -> Input {
    Input::Key(KeyInput {
        key: "w".parse().expect("w"),
        text: Some('w'),
        kind,
    })
}

/// The console's loop on a fake clock: each input recorded, handled, its commands recorded,
/// then the message line and the fence; deadlines ticked as the runtime's timer fires them.
struct Live {
    app: App,
    recorder: Option<Recorder>,
    base: Instant,
}

impl Live {
    fn new(config: AppConfig, path: PathBuf) -> Live {
        let base = Instant::now();
        let mut app = App::new(config.clone(), PositionBook::new());
        let resize = Input::Resize {
            width: WIDTH,
            height: HEIGHT,
        };
        app.handle(resize, base);
        let mut recorder = Recorder::start(path, QUEUE).expect("recording");
        recorder.set_clock(START_NS);
        recorder.session(&config, "sim");
        Live {
            app,
            recorder: Some(recorder),
            base,
        }
    }

    fn recorder(&mut self) -> &mut Recorder {
        self.recorder.as_mut().expect("recording")
    }

    fn handle(&mut self, input: Input, now: Instant) {
        let ns = START_NS + u64::try_from((now - self.base).as_nanos()).expect("ns");
        self.recorder().set_clock(ns);
        self.recorder().input(&input);
        let effects = self.app.handle(input, now);
        for effect in effects {
            if let Effect::Arm(command) = effect {
                self.recorder().command(&command);
            }
        }
        let message = self.app.message().map(|(t, s)| (t.to_string(), s));
        let fence = self.app.fence_text();
        let recorder = self.recorder();
        recorder.said(message.as_ref().map(|(t, s)| (t.as_str(), *s)));
        recorder.fence(fence);
        recorder.hand_over();
    }

    fn ticks_until(&mut self, at: Instant) {
        while let Some(deadline) = self.app.next_deadline().filter(|d| *d <= at) {
            self.handle(Input::Tick, deadline);
            if self.app.next_deadline() == Some(deadline) {
                break;
            }
        }
    }

    fn at(&mut self, ms: u64, input: Input) {
        let now = self.base + Duration::from_millis(ms);
        self.ticks_until(now);
        self.handle(input, now);
    }

    /// The screen at `ms`, as the painter would draw it then.
    fn screen(&mut self, ms: u64) -> Vec<String> {
        self.ticks_until(self.base + Duration::from_millis(ms));
        rows(&View::new(&self.app))
    }

    fn finish(&mut self) {
        // Dropped: the summary written.
        self.recorder.take();
    }
}

fn rows(view: &View) -> Vec<String> {
    let mut terminal = Terminal::new(TestBackend::new(WIDTH, HEIGHT)).expect("terminal");
    terminal
        .draw(|f| ui::draw(f, view, &Theme { color: false }))
        .expect("draw");
    let buffer = terminal.backend().buffer();
    (0..HEIGHT)
        .map(|y| (0..WIDTH).map(|x| buffer[(x, y)].symbol()).collect())
        .collect()
}

fn config() -> AppConfig {
    // What `armjog replay` starts the app with for this session: the same as live.
    let mut config = config_of(None);
    config.simulated = true;
    config.positions_on_operator = true;
    config
}

/// When the screens are compared (ms from the start): at rest, jogging, stopping, stopped,
/// in fault, refusing, after.
const LOOKS: [u64; 7] = [500, 1500, 1815, 1900, 2600, 2720, 2970];

/// The session: runs it live, recording into `path`; the live screens at [`LOOKS`].
fn session(path: &Path) -> Vec<Vec<String>> {
    let mut live = Live::new(config(), path.to_path_buf());
    let up = LinkStatus::Up {
        description: "talos 127.0.0.1:61616 (icd, crc16), operator 1.0".into(),
    };
    live.at(0, Input::Arm(ArmEvent::Status(up)));
    live.at(
        1,
        Input::Arm(ArmEvent::TelemetrySource(TelemetrySource::TalosHardware)),
    );
    live.at(2, Input::Arm(ArmEvent::Speed(50)));
    let mut screens = Vec::new();
    let mut looks = LOOKS.iter().peekable();
    let mut x = 0.0;
    for n in 0..91u64 {
        let ms = 10 + n * 33;
        while let Some(look) = looks.next_if(|look| **look < ms) {
            screens.push(live.screen(*look));
        }
        match ms {
            1000..1033 => live.at(1000, key(KeyKind::Press)),
            1033..1066 => {
                let mut entry = LogEntry::new("cart_start", "OK".into());
                entry.id = Some(5);
                entry.ok = true;
                entry.latency = Some(Duration::from_micros(1200));
                live.at(1040, Input::Arm(ArmEvent::Log(entry)));
            }
            1792..1825 => {
                live.at(1800, key(KeyKind::Release));
                let mut entry = LogEntry::new("stop", "OK".into());
                entry.ok = true;
                live.at(1802, Input::Arm(ArmEvent::Log(entry)));
                live.at(1803, Input::Arm(ArmEvent::StopConfirmed));
            }
            2692..2725 => live.at(2700, key(KeyKind::Press)),
            2758..2791 => live.at(2760, key(KeyKind::Release)),
            _ => {}
        }
        let moving = (1000..1850).contains(&ms);
        if moving {
            x += 3.3;
        }
        let t = sample(x, x / 100.0, moving, ms >= 2500);
        live.at(ms, Input::Arm(ArmEvent::Telemetry(Box::new(t))));
    }
    for look in looks {
        screens.push(live.screen(*look));
    }
    live.finish();
    screens
}

#[test]
fn at_x1_the_panels_show_what_the_console_showed_live_at_the_same_times() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("session.mcap");
    let live = session(&path);
    let recording = Recording::read(&path).expect("a recording");
    assert_eq!(recording.cut_short, None);
    assert!(recording.skipped.is_empty(), "{:?}", recording.skipped);
    let mut player = Player::new(recording, (WIDTH, HEIGHT), Instant::now());
    let mut played_at = START_NS;
    for (look, live) in LOOKS.iter().zip(&live) {
        // Played at ×1 from the start: as much time passes as passed live.
        let at = START_NS + look * 1_000_000;
        player.play(Duration::from_nanos(at - played_at));
        played_at = at;
        assert_eq!(player.at_ns(), at);
        let replay = rows(&player.view());
        // The link line says REPLAY before anything; the rest is what the console showed.
        assert!(replay[0].starts_with(" REPLAY 18:03:0"), "{}", replay[0]);
        assert!(replay[0].contains(" ×1 "), "{}", replay[0]);
        let (_, after_badge) = replay[0].split_once(" ×1 ").expect("the badge");
        assert_eq!(after_badge.trim(), live[0].trim(), "at {look} ms");
        let last = usize::from(HEIGHT) - 1;
        for y in 1..last {
            assert_eq!(replay[y], live[y], "at {look} ms, row {y}");
        }
        // The bottom line: the same message; with none, playback's keys, not the console's.
        let footer = live[last].starts_with("space ") || live[last].contains("jog");
        if footer {
            assert!(replay[last].starts_with("space pause"), "{}", replay[last]);
        } else {
            assert_eq!(replay[last], live[last], "at {look} ms");
        }
    }
    // What the screens showed, so that the comparison above compared something.
    assert!(live[1][1].contains("JOG +X"), "{}", live[1][1]);
    assert!(live[4][1].contains("in_fault") || live[4].iter().any(|r| r.contains("joint_fault")));
    let refused = &live[5][usize::from(HEIGHT) - 1];
    assert!(
        refused.contains("refused") || refused.contains("fault"),
        "{refused}"
    );
}

#[test]
fn the_replay_screen_says_replay_and_its_keys() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("session.mcap");
    session(&path);
    let mut player = Player::new(
        Recording::read(&path).expect("a recording"),
        (WIDTH, HEIGHT),
        Instant::now(),
    );
    player.seek(START_NS + 1_500_000_000);
    insta::assert_snapshot!("replay_jogging", rows(&player.view()).join("\n"));
}

fn press(player: &mut Player, name: &str) -> Control {
    let key = KeyInput {
        key: name.parse().expect("a key"),
        text: None,
        kind: KeyKind::Press,
    };
    player.on_key(&key)
}

#[test]
fn playback_keys_pause_step_change_speed_and_jump_and_never_reach_the_app() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("session.mcap");
    session(&path);
    let recording = Recording::read(&path).expect("a recording");
    let (first, last) = (recording.first_ns, recording.last_ns);
    assert_eq!(first, START_NS);
    let mut player = Player::new(recording, (WIDTH, HEIGHT), Instant::now());
    assert!(player.status().starts_with("REPLAY 18:03:05.000 ×1"));
    let second = 1_000_000_000;
    assert_eq!(press(&mut player, "space"), Control::Continue);
    player.play(Duration::from_secs(1));
    assert_eq!(player.at_ns(), first, "paused");
    assert!(player.status().ends_with("PAUSED"), "{}", player.status());
    press(&mut player, "right");
    assert_eq!(player.at_ns(), first + second);
    press(&mut player, "shift+right");
    assert_eq!(player.at_ns(), last, "10 s on is past the end: the end");
    assert!(player.status().ends_with("END"), "{}", player.status());
    press(&mut player, "left");
    assert_eq!(player.at_ns(), last - second);
    press(&mut player, "home");
    assert_eq!(player.at_ns(), first);
    press(&mut player, "end");
    assert_eq!(player.at_ns(), last);
    press(&mut player, "home");
    press(&mut player, "+");
    press(&mut player, "space");
    player.play(Duration::from_millis(500));
    assert_eq!(player.at_ns(), first + second, "×2");
    assert!(player.status().contains(" ×2"), "{}", player.status());
    press(&mut player, "-");
    press(&mut player, "-");
    player.play(Duration::from_millis(500));
    assert_eq!(player.at_ns(), first + second + second / 4, "×0.5");
    // A jog key is not the app's: nothing jogs, nothing changes on screen.
    player.seek(first + 500_000_000);
    let before = player.view();
    press(&mut player, "w");
    press(&mut player, "space");
    assert_eq!(player.view().keys, before.keys);
    // Stepping back replays from a kept copy: the same screen as playing to there.
    player.seek(first + 2_600_000_000);
    let forward = rows(&player.view());
    player.seek(last);
    player.seek(first + 2_600_000_000);
    assert_eq!(rows(&player.view())[1..], forward[1..]);
    assert_eq!(press(&mut player, "q"), Control::Quit);
}

#[test]
fn telemetry_reads_back_as_the_same_sample_odd_values_and_all() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("odd.mcap");
    let mut odd = sample(12.345_678, 0.1, true, true);
    odd.joints[3].torque = f32::NAN;
    odd.tcp.wrench.force_z = -0.000_123_4;
    odd.warnings = FlagSet::from_bits(1 << 31);
    odd.robot_state = Coded::Unknown(65_535);
    odd.arm.voltage = 23.987_654;
    odd.speed_limits.linear = 0.5;
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    recorder.input(&Input::Arm(ArmEvent::Telemetry(Box::new(odd.clone()))));
    drop(recorder);
    let recording = Recording::read(&path).expect("a recording");
    let samples: Vec<&Telemetry> = recording
        .events
        .iter()
        .filter_map(|(_, happened)| match happened {
            Happened::Input(Input::Arm(ArmEvent::Telemetry(t))) => Some(&**t),
            _ => None,
        })
        .collect();
    assert_eq!(samples.len(), 1);
    // NaN is not equal to itself: compared as words, every digit.
    let words = |t: &Telemetry| {
        format!(
            "{:?}",
            Telemetry {
                control: Coded::Unknown(0),
                ..t.clone()
            }
        )
    };
    assert_eq!(words(samples[0]), words(&odd));
    assert!(samples[0].joints[3].torque.is_nan());
    assert_eq!(samples[0].warnings.names(), ["unknown_bit_31"]);
}

#[test]
fn a_file_cut_short_plays_to_its_last_good_message_and_a_foreign_one_is_refused() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("two-chunks.mcap");
    // Two chunks: the recorder closes one a second.
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    for n in 0..40 {
        if n == 20 {
            recorder.hand_over();
            std::thread::sleep(armjog::console::recorder::FLUSH_EVERY + Duration::from_millis(300));
        }
        let t = sample(n as f32, 0.0, false, false);
        recorder.input(&Input::Arm(ArmEvent::Telemetry(Box::new(t))));
        recorder.input(&key(KeyKind::Press));
    }
    drop(recorder);
    let bytes = std::fs::read(&path).expect("read");
    let whole = Recording::parse(&bytes).expect("whole");
    assert_eq!(whole.cut_short, None);
    assert_eq!(whole.events.len(), 80);
    let mut played_cut = None;
    for tenth in 1..10 {
        // Never a panic: played up to the cut, or refused in words.
        match Recording::parse(&bytes[..bytes.len() * tenth / 10]) {
            Ok(cut) if cut.events.len() < whole.events.len() => played_cut = Some(cut),
            Ok(_) => {}
            Err(RecordingError::NotMcap(..) | RecordingError::Empty(_)) => {}
            Err(other) => panic!("{other}"),
        }
    }
    let cut = played_cut.expect("a cut inside the second chunk plays the first");
    assert_eq!(cut.events.len(), 40, "the first chunk, whole");
    assert!(cut.cut_short.is_some());
    let player = Player::new(cut, (WIDTH, HEIGHT), Instant::now());
    let bottom = rows(&player.view())[usize::from(HEIGHT) - 1].clone();
    assert!(bottom.contains("recording cut short"), "{bottom}");
    for foreign in [&b"not an mcap file\n"[..], &[], &bytes[..20]] {
        match Recording::parse(foreign) {
            Err(RecordingError::NotMcap(..) | RecordingError::Empty(_)) => {}
            other => panic!("{:?}", other.map(|r| r.events.len())),
        }
    }
}

#[test]
fn a_file_with_channels_this_armjog_does_not_know_plays_the_rest_and_says_what_it_skipped() {
    let dir = tempfile::tempdir().expect("a folder");
    let ours = dir.path().join("ours.mcap");
    session(&ours);
    let bytes = std::fs::read(&ours).expect("read");
    // The same session with a channel from elsewhere and one an older armjog wrote.
    let mixed = dir.path().join("mixed.mcap");
    let file = std::fs::File::create(&mixed).expect("created");
    let mut writer = mcap::Writer::new(std::io::BufWriter::new(file)).expect("a writer");
    let mut channels = std::collections::BTreeMap::new();
    let mut extra = None;
    for message in mcap::MessageStream::new(&bytes).expect("ours") {
        let message = message.expect("a message");
        let id = *channels
            .entry(message.channel.topic.clone())
            .or_insert_with(|| {
                writer
                    .add_channel(0, &message.channel.topic, "json", &Default::default())
                    .expect("a channel")
            });
        let extra_ids = *extra.get_or_insert_with(|| {
            let gripper = writer
                .add_channel(0, "/gripper/state", "json", &Default::default())
                .expect("gripper");
            let old = writer
                .add_channel(0, "/tool/twist_wrench", "json", &Default::default())
                .expect("old");
            (gripper, old)
        });
        let header = |channel_id| mcap::records::MessageHeader {
            channel_id,
            sequence: 0,
            log_time: message.log_time,
            publish_time: message.log_time,
        };
        writer
            .write_to_known_channel(&header(id), &message.data)
            .expect("written");
        writer
            .write_to_known_channel(&header(extra_ids.0), b"{\"open\":true}")
            .expect("written");
        writer
            .write_to_known_channel(&header(extra_ids.1), b"{}")
            .expect("written");
    }
    writer.finish().expect("finished");
    drop(writer);
    let whole = Recording::read(&ours).expect("ours");
    let recording = Recording::read(&mixed).expect("played");
    assert_eq!(
        recording
            .skipped
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        ["/gripper/state", "/tool/twist_wrench"]
    );
    assert_eq!(recording.events, whole.events, "the rest plays as ever");
    let mut player = Player::new(recording, (WIDTH, HEIGHT), Instant::now());
    player.seek(START_NS + 500_000_000);
    let bottom = rows(&player.view())[usize::from(HEIGHT) - 1].clone();
    assert!(
        bottom.contains("skipped: /gripper/state, /tool/twist_wrench"),
        "{bottom}"
    );
}

#[test]
fn a_damaged_file_is_played_to_the_damage_or_refused_never_a_panic() {
    let dir = tempfile::tempdir().expect("a folder");
    let path = dir.path().join("short.mcap");
    let mut recorder = Recorder::start(path.clone(), QUEUE).expect("recording");
    recorder.input(&Input::Arm(ArmEvent::Telemetry(Box::new(sample(
        0.0, 0.0, false, false,
    )))));
    recorder.input(&key(KeyKind::Press));
    drop(recorder);
    let bytes = std::fs::read(&path).expect("read");
    let started = Instant::now();
    let mut played = 0;
    let mut chunk_refused = 0;
    // Every byte in turn set to another value (two in five to a third): lengths, opcodes,
    // sizes, compressed data. A chunk saying it holds a few bytes more than it does once made
    // the `mcap` reader loop for ever; a few bytes less, overflow.
    for at in 0..bytes.len() {
        let values: &[u8] = if at % 5 < 2 { &[0x00, 0x7f] } else { &[0xff] };
        for &value in values {
            let mut damaged = bytes.clone();
            damaged[at] = value;
            let parsed = Recording::parse(&damaged);
            let said = match &parsed {
                Ok(recording) => recording.cut_short.clone().unwrap_or_default(),
                Err(e) => e.to_string(),
            };
            chunk_refused += usize::from(said.contains("damaged chunk"));
            if let Ok(recording) = parsed {
                // Drawn now and then: the panels take what was read, whatever it says.
                if at % 97 == 0 {
                    let player = Player::new(recording, (WIDTH, HEIGHT), Instant::now());
                    rows(&player.view());
                }
                played += 1;
            }
        }
    }
    assert!(played > 0);
    assert!(chunk_refused > 0, "no damaged chunk said so");
    eprintln!("{} bytes damaged in {:?}", bytes.len(), started.elapsed());
}
