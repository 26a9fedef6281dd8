//! The simulated Talos operator through real sockets: each command's effect on the arm, the
//! watchdog, error codes, garbage and injected network faults.
//!
//! The tests that time the arm (the watchdog, moves of a given length, the ack dialect) run on
//! tokio's paused clock: the simulator integrates in tokio time, so their sleeps are exact
//! however loaded the machine is. The clock only jumps when every task waits, to the next timer
//! (the simulator's 10 ms tick at the farthest), so a socket round trip costs at most a tick.

use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;

use armjog::link::{Answer, Dialect, TalosConfig, TalosError, TalosLink};
use armjog::sim::talos_server::NetworkFaults;
use armjog::sim::{SimConfig, Simulator};
use armjog::talos::{Checksum, Reply, Request, ReturnCode, TalosFrame};

async fn sim() -> Simulator {
    Simulator::start(SimConfig::ephemeral())
        .await
        .expect("simulator starts")
}

async fn link(sim: &Simulator) -> TalosLink {
    let mut config = TalosConfig::new(sim.talos_addr.to_string());
    config.request_timeout = Duration::from_millis(400);
    TalosLink::connect(config).await.expect("connect").0
}

async fn tcp(sim: &Simulator) -> [f64; 3] {
    sim.arm.snapshot().await.unwrap().tcp_position
}

async fn code_of(link: &TalosLink, request: Request) -> ReturnCode {
    match link.request(request).await {
        Ok(exchange) => exchange.return_code(),
        Err(TalosError::ReturnCode { exchange }) => exchange.return_code(),
        Err(e) => panic!("link error: {e}"),
    }
}

#[tokio::test]
async fn handshake_and_speed_over_tcp() {
    let sim = sim().await;
    let link = link(&sim).await;
    assert_eq!(link.handshake(1).await.unwrap(), Some((1, 0)));
    assert_eq!(
        code_of(&link, Request::SetSpeed { speed: 20 }).await,
        ReturnCode::OK
    );
    let exchange = link.request(Request::GetSpeed).await.unwrap();
    assert!(matches!(
        exchange.answer,
        Answer::Reply(Reply::GetSpeed { speed: 20, .. })
    ));
    assert_eq!(
        code_of(&link, Request::SetSpeed { speed: 0 }).await,
        ReturnCode::OUT_OF_RANGE
    );
    assert_eq!(
        code_of(&link, Request::SetSpeed { speed: 101 }).await,
        ReturnCode::OUT_OF_RANGE
    );
}

#[tokio::test(start_paused = true)]
async fn a_continuous_cartesian_start_moves_plus_x_and_stop_halts_it() {
    let sim = sim().await;
    let link = link(&sim).await;
    let before = tcp(&sim).await;
    let start = Request::CartesianMoveStart {
        moving_x: 1,
        moving_y: 0,
        moving_z: 0,
    };
    link.request(start).await.unwrap();
    tokio::time::sleep(Duration::from_millis(200)).await;
    link.request(Request::CartesianMoveStop).await.unwrap();
    let stopped = tcp(&sim).await;
    assert!(
        stopped[0] - before[0] > 0.01,
        "moved +X: {before:?} -> {stopped:?}"
    );
    assert!((stopped[1] - before[1]).abs() < 0.003 && (stopped[2] - before[2]).abs() < 0.003);
    tokio::time::sleep(Duration::from_millis(100)).await;
    let later = tcp(&sim).await;
    assert!((later[0] - stopped[0]).abs() < 1e-6, "no motion after STOP");
}

#[tokio::test(start_paused = true)]
async fn the_watchdog_stops_a_start_that_is_not_refreshed() {
    let sim = sim().await;
    let link = link(&sim).await;
    link.request(Request::PolarPanStart {
        moving_azimuth: 1,
        moving_altitude: 0,
    })
    .await
    .unwrap();
    tokio::time::sleep(Duration::from_millis(250)).await;
    assert!(
        sim.arm.snapshot().await.unwrap().moving,
        "still moving at 250 ms"
    );
    // 500 ms watchdog plus one 1 ms integrator step, plus the ticks the START's round trip took.
    tokio::time::sleep(Duration::from_millis(300)).await;
    let snapshot = sim.arm.snapshot().await.unwrap();
    assert!(!snapshot.moving, "stopped by the watchdog");
}

#[tokio::test(start_paused = true)]
async fn refreshing_start_keeps_the_motion_alive_past_the_watchdog() {
    let sim = sim().await;
    let link = link(&sim).await;
    let start = Request::CartesianMoveStart {
        moving_x: 0,
        moving_y: 0,
        moving_z: 1,
    };
    for _ in 0..8 {
        link.request(start.clone()).await.unwrap();
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
    assert!(
        sim.arm.snapshot().await.unwrap().moving,
        "800 ms of refreshed START"
    );
    link.request(Request::CartesianMoveStop).await.unwrap();
}

#[tokio::test(start_paused = true)]
async fn a_silent_client_mid_jog_is_stopped_by_the_watchdog() {
    let sim = sim().await;
    // A raw client that freezes without STOP but keeps its connection open (a client that
    // closes is stopped at once: talos_disconnect.rs).
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    let frame = Request::CartesianMoveStart {
        moving_x: -1,
        moving_y: 0,
        moving_z: 0,
    }
    .to_frame(0)
    .unwrap();
    stream
        .write_all(&frame.to_bytes(Checksum::Crc16).unwrap())
        .await
        .unwrap();
    let mut reply = [0u8; 14];
    stream.read_exact(&mut reply).await.unwrap();
    assert!(sim.arm.snapshot().await.unwrap().moving);
    tokio::time::sleep(Duration::from_millis(600)).await;
    assert!(!sim.arm.snapshot().await.unwrap().moving);
    drop(stream);
}

#[tokio::test]
async fn named_positions_round_trip_and_unknown_names_are_refused() {
    let sim = sim().await;
    let link = link(&sim).await;
    let save = Request::SavePosition {
        name: "bench".into(),
        anchor: false,
        parent: String::new(),
    };
    assert_eq!(code_of(&link, save).await, ReturnCode::OK);
    let exchange = link
        .request(Request::GetCartesianPosition {
            name: "bench".into(),
        })
        .await
        .unwrap();
    let Answer::Reply(Reply::GetCartesianPosition { x, y, z, .. }) = exchange.answer else {
        panic!("{:?}", exchange.answer)
    };
    assert!((x - 4566).abs() <= 10 && (y - 10).abs() <= 10 && (z - 4338).abs() <= 10);
    assert_eq!(
        code_of(
            &link,
            Request::GoToPosition {
                name: "elsewhere".into()
            }
        )
        .await,
        ReturnCode::UNKNOWN_POSITION
    );
    assert_eq!(
        code_of(
            &link,
            Request::DeletePosition {
                name: "bench".into()
            }
        )
        .await,
        ReturnCode::OK
    );
    assert_eq!(
        code_of(
            &link,
            Request::GetPolarPosition {
                name: "bench".into()
            }
        )
        .await,
        ReturnCode::UNKNOWN_POSITION
    );
}

#[tokio::test]
async fn home_brings_the_arm_back() {
    let sim = sim().await;
    let link = link(&sim).await;
    let home = tcp(&sim).await;
    let nudge = Request::CartesianMove {
        delta_x: -300,
        delta_y: 300,
        delta_z: 0,
        delay_ms: 0,
        time_ms: 200,
    };
    link.request(nudge).await.unwrap();
    tokio::time::sleep(Duration::from_millis(700)).await;
    assert!((tcp(&sim).await[1] - home[1]).abs() > 0.02);
    assert_eq!(
        code_of(&link, Request::SetSpeed { speed: 100 }).await,
        ReturnCode::OK
    );
    link.request(Request::Home { delay_ms: 0 }).await.unwrap();
    tokio::time::sleep(Duration::from_millis(1500)).await;
    let back = tcp(&sim).await;
    for k in 0..3 {
        assert!((back[k] - home[k]).abs() < 2e-3, "{back:?} vs {home:?}");
    }
}

/// Sends raw bytes and reads one reply frame (crc16) of `len` bytes.
async fn raw_exchange(sim: &Simulator, bytes: &[u8], len: usize) -> Vec<u8> {
    let mut stream = TcpStream::connect(sim.talos_addr).await.unwrap();
    stream.write_all(bytes).await.unwrap();
    let mut reply = vec![0u8; len];
    tokio::time::timeout(Duration::from_secs(1), stream.read_exact(&mut reply))
        .await
        .expect("a reply")
        .unwrap();
    reply
}

fn return_code_of(reply: &[u8]) -> u16 {
    u16::from_be_bytes([reply[10], reply[11]])
}

#[tokio::test]
async fn unknown_commands_malformed_payloads_and_bad_checksums_get_their_codes() {
    let sim = sim().await;
    // Command 0x0042 does not exist.
    let unknown = TalosFrame::new(4, 0x0042, vec![])
        .to_bytes(Checksum::Crc16)
        .unwrap();
    let reply = raw_exchange(&sim, &unknown, 14).await;
    assert_eq!(&reply[..10], &[0, 0, 0, 5, 0, 0, 0x80, 0x42, 0, 2]);
    assert_eq!(return_code_of(&reply), 0x0001);
    // Set Speed with two payload bytes instead of one.
    let malformed = TalosFrame::new(6, 0x000A, vec![1, 2])
        .to_bytes(Checksum::Crc16)
        .unwrap();
    let reply = raw_exchange(&sim, &malformed, 14).await;
    assert_eq!(&reply[6..8], &[0x80, 0x0A]);
    assert_eq!(return_code_of(&reply), 0x0002);
    // Get Speed with a corrupt checksum: the full Get Speed reply layout (rc + speed = 3 bytes).
    let mut corrupt = Request::GetSpeed
        .to_frame(8)
        .unwrap()
        .to_bytes(Checksum::Crc16)
        .unwrap();
    let last = corrupt.len() - 1;
    corrupt[last] ^= 0x55;
    let reply = raw_exchange(&sim, &corrupt, 14).await;
    assert_eq!(&reply[..4], &[0, 0, 0, 9]);
    assert_eq!(return_code_of(&reply), 0x0003);
}

#[tokio::test]
async fn garbage_does_not_kill_the_server_or_lose_the_next_frame() {
    let sim = sim().await;
    let mut bytes: Vec<u8> = (0..500u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    bytes.extend(
        Request::GetSpeed
            .to_frame(10)
            .unwrap()
            .to_bytes(Checksum::Crc16)
            .unwrap(),
    );
    let reply = raw_exchange(&sim, &bytes, 15).await;
    assert_eq!(&reply[..8], &[0, 0, 0, 11, 0, 0, 0x80, 0x09]);
    // And the server still takes new clients.
    let link = link(&sim).await;
    assert!(link.handshake(0).await.is_ok());
}

#[tokio::test]
async fn several_clients_drive_the_same_arm() {
    let sim = sim().await;
    let (a, b) = (link(&sim).await, link(&sim).await);
    a.request(Request::SetSpeed { speed: 33 }).await.unwrap();
    let exchange = b.request(Request::GetSpeed).await.unwrap();
    assert!(matches!(
        exchange.answer,
        Answer::Reply(Reply::GetSpeed { speed: 33, .. })
    ));
}

#[tokio::test]
async fn injected_delay_and_dropped_replies_time_the_link_out() {
    let sim = sim().await;
    let link = link(&sim).await;
    sim.set_faults(NetworkFaults {
        reply_delay: Duration::from_millis(600),
        ..Default::default()
    });
    let err = link.request(Request::GetSpeed).await.unwrap_err();
    assert!(matches!(err, TalosError::Timeout { .. }), "{err:?}");
    sim.set_faults(NetworkFaults {
        drop_every_nth_reply: 1,
        ..Default::default()
    });
    let err = link.request(Request::GetSpeed).await.unwrap_err();
    assert!(matches!(err, TalosError::Timeout { .. }), "{err:?}");
    sim.set_faults(NetworkFaults::default());
    tokio::time::sleep(Duration::from_millis(300)).await;
    assert!(link.request(Request::GetSpeed).await.is_ok());
}

#[tokio::test]
async fn an_injected_disconnect_is_seen_by_the_link() {
    let sim = sim().await;
    sim.set_faults(NetworkFaults {
        close_after_frames: Some(1),
        ..Default::default()
    });
    let link = link(&sim).await;
    let _ = link.request(Request::GetSpeed).await;
    let err = link.request(Request::GetSpeed).await.unwrap_err();
    assert!(matches!(err, TalosError::Disconnected { .. }), "{err:?}");
}

#[tokio::test(start_paused = true)]
async fn the_ack_dialect_imitates_the_deployed_operator() {
    let mut config = SimConfig::ephemeral();
    config.talos.dialect = Dialect::Ack;
    config.talos.checksum = Checksum::Xor8;
    let sim = Simulator::start(config).await.unwrap();
    let mut c = TalosConfig::new(sim.talos_addr.to_string());
    c.dialect = Dialect::Ack;
    c.checksum = Checksum::Xor8;
    let (link, _) = TalosLink::connect(c).await.unwrap();
    let exchange = link
        .request(Request::PolarPanStart {
            moving_azimuth: 1,
            moving_altitude: 0,
        })
        .await
        .unwrap();
    assert_eq!(exchange.answer, Answer::Ack);
    tokio::time::sleep(Duration::from_millis(50)).await;
    assert!(sim.arm.snapshot().await.unwrap().moving);
    link.request(Request::PolarPanStop).await.unwrap();
    tokio::time::sleep(Duration::from_millis(20)).await;
    assert!(!sim.arm.snapshot().await.unwrap().moving);
}

#[tokio::test]
async fn a_taken_port_is_refused_with_a_clear_message() {
    let sim = sim().await;
    let mut config = SimConfig::ephemeral();
    config.talos_listen = sim.talos_addr.to_string();
    let err = Simulator::start(config).await.err().expect("port taken");
    let message = err.to_string();
    assert!(
        message.contains("Talos operator") && message.contains("--talos-listen"),
        "{message}"
    );
}
