//! The console against the simulator over real sockets, through a TCP relay that can freeze
//! (stop forwarding both ways, connections left open): a frozen network while jogging over
//! Modbus must show as LINK STALE and MAY BE MOVING (the arm has no twist watchdog, and the
//! STOP cannot get through), never as a healthy idle arm. The state machine gets the real
//! driver's events, as the runtime would deliver them.

use armjog::console::app::QUESTION_QUIET;
use std::net::SocketAddr;
use std::time::{Duration, Instant};

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::mpsc::UnboundedReceiver;
use tokio::sync::watch;

use armjog::console::app::{App, Input, MotionShown};
use armjog::console::jog::KeyKind;
use armjog::console::positions::PositionBook;
use armjog::link::driver::{Driver, DriverConfig};
use armjog::link::interface::{ArmEvent, LinkStatus};
use armjog::link::{ModbusConfig, TalosConfig};
use armjog::sim::arm_model::Arm;
use armjog::sim::kinematics::to_radians;
use armjog::sim::{SimConfig, Simulator};

use crate::event_loop::{self, Drives};

/// Forwards TCP connections to `target` until frozen; frozen, it holds every byte (and keeps
/// accepting connections it does not serve), like a network that stopped.
struct Relay {
    addr: SocketAddr,
    frozen: watch::Sender<bool>,
}

impl Relay {
    async fn start(target: SocketAddr) -> Relay {
        let listener = TcpListener::bind("127.0.0.1:0").await.expect("bind relay");
        let addr = listener.local_addr().expect("relay address");
        let (frozen, thawed) = watch::channel(false);
        tokio::spawn(async move {
            while let Ok((inbound, _)) = listener.accept().await {
                let Ok(outbound) = TcpStream::connect(target).await else {
                    continue;
                };
                let (from_client, to_client) = inbound.into_split();
                let (from_server, to_server) = outbound.into_split();
                tokio::spawn(pipe(from_client, to_server, thawed.clone()));
                tokio::spawn(pipe(from_server, to_client, thawed.clone()));
            }
        });
        Relay { addr, frozen }
    }

    fn freeze(&self, frozen: bool) {
        self.frozen.send_replace(frozen);
    }
}

async fn pipe(mut from: OwnedReadHalf, mut to: OwnedWriteHalf, mut frozen: watch::Receiver<bool>) {
    let mut buf = [0u8; 4096];
    loop {
        let n = match from.read(&mut buf).await {
            Ok(0) | Err(_) => return,
            Ok(n) => n,
        };
        if frozen.wait_for(|f| !*f).await.is_err() || to.write_all(&buf[..n]).await.is_err() {
            return;
        }
    }
}

struct Console {
    app: App,
    driver: Driver,
    events: UnboundedReceiver<ArmEvent>,
    sim: Simulator,
    relay: Relay,
    /// Every motion state shown since the last `clear_seen`, in order.
    seen: Vec<MotionShown>,
    seen_stale: bool,
    /// Every message shown since the last `said.clear()`, in order.
    said: Vec<String>,
}

impl event_loop::Drives for Console {
    fn app(&self) -> &App {
        &self.app
    }
    fn events(&mut self) -> &mut UnboundedReceiver<ArmEvent> {
        &mut self.events
    }
    fn input(&mut self, input: Input) {
        Console::input(self, input);
    }
}

impl Console {
    /// Over Modbus through the relay, to a simulated arm at home.
    async fn start() -> Console {
        Console::start_with(Arm::default(), false).await
    }

    /// To a simulated `arm`, over Modbus through the relay, or over Talos (`talos`, direct).
    async fn start_with(arm: Arm, talos: bool) -> Console {
        let mut sim_config = SimConfig::ephemeral();
        sim_config.arm = arm;
        let sim = Simulator::start(sim_config).await.expect("simulator");
        let relay = Relay::start(sim.modbus_addr.expect("modbus server")).await;
        let mut modbus = ModbusConfig::new(relay.addr.to_string());
        // A slow arm's reply timeout: the link is stale well before it gives up on a request.
        modbus.request_timeout = Duration::from_secs(3);
        let config = match talos {
            true => DriverConfig::new(Some(TalosConfig::new(sim.talos_addr.to_string())), None),
            false => DriverConfig::new(None, Some(modbus)),
        };
        let app = event_loop::app_for(&config, PositionBook::new());
        let (driver, events) = Driver::spawn(config);
        let mut console = Console {
            app,
            driver,
            events,
            sim,
            relay,
            seen: Vec::new(),
            seen_stale: false,
            said: Vec::new(),
        };
        console
            .run_until(Duration::from_secs(5), |c| {
                matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.telemetry().is_some()
            })
            .await;
        console
    }

    fn input(&mut self, input: Input) {
        event_loop::carry_out(&mut self.app, &self.driver, input);
        let shown = self.app.motion_shown();
        if self.seen.last() != Some(&shown) {
            self.seen.push(shown);
        }
        self.seen_stale |= self.app.link_stale().is_some();
        let text = message(self);
        if !text.is_empty() && self.said.last() != Some(&text) {
            self.said.push(text);
        }
    }

    async fn moving(&self) -> bool {
        self.sim.arm.snapshot().await.expect("sim").moving
    }
}

fn may_be_moving(c: &Console) -> bool {
    matches!(c.app.motion_shown(), MotionShown::MayBeMoving(_))
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_network_that_freezes_mid_jog_shows_link_stale_and_may_be_moving() {
    let mut console = Console::start().await;
    console.key("w", KeyKind::Press);
    console.run_for(Duration::from_millis(300)).await;
    assert!(console.moving().await, "jogging");
    assert!(console.app.link_stale().is_none());

    console.relay.freeze(true);
    console.seen.clear();
    console
        .run_until(Duration::from_secs(10), |c| {
            c.seen_stale && !c.app.jog().is_jogging() && may_be_moving(c)
        })
        .await;
    // The key is still held: only the stale link stopped the jog.
    assert!(
        console.seen.iter().all(|s| *s != MotionShown::Idle),
        "never idle while frozen: {:?}",
        console.seen
    );
    assert!(
        console.moving().await,
        "the STOP cannot get through: the arm does move"
    );
    // It keeps saying so while the network stays frozen, whatever the link does meanwhile.
    console.run_for(Duration::from_secs(1)).await;
    assert!(may_be_moving(&console), "{:?}", console.app.motion_shown());
    assert!(
        console.seen.iter().all(|s| *s != MotionShown::Idle),
        "{:?}",
        console.seen
    );

    // The network comes back: a STOP now gets through, and the screen says idle only once the
    // STOP is confirmed and the arm is seen at rest.
    console.key("w", KeyKind::Release);
    console.relay.freeze(false);
    console
        .run_until(Duration::from_secs(10), |c| {
            matches!(c.app.link(), LinkStatus::Up { .. }) && c.app.link_stale().is_none()
        })
        .await;
    console.key("space", KeyKind::Press);
    console
        .run_until(Duration::from_secs(10), |c| {
            c.app.motion_shown() == MotionShown::Idle
        })
        .await;
    assert!(!console.moving().await, "idle is the motion_truth");
}

fn message(c: &Console) -> String {
    crate::app_support::message(&c.app)
}

fn moving_home(c: &Console) -> bool {
    matches!(&c.app.motion_shown(), MotionShown::Action { label, confirmed: true } if label == "HOME")
}

/// An arm away from home, within every joint limit.
fn away() -> Arm {
    Arm::at(to_radians(&[10.0, 30.0, 170.0, 240.0, 10.0, 40.0, 80.0]))
}

/// J4 2.3 degrees short of its limit, the tool at (-199, -231, 435) mm. A 100 mm step along
/// +X ends where J4 is within its limit (the arm accepts it), but the straight line there
/// passes closer to the shoulder than the folded elbow allows: the arm stops at J4's limit
/// about 58 mm along, with a joint-fault warning. (Found with `sim::arm_model::Arm` directly; the
/// simulator's home is a joint-space move and never passes a limit.)
fn step_through_j4_limit() -> Arm {
    Arm::at(to_radians(&[0.0, 19.0, 135.0, 145.5, 0.0, -25.0, 90.0]))
}

async fn home(console: &mut Console) {
    console.key("h", KeyKind::Press);
    // A question ignores keys for its first moments.
    console
        .run_for(QUESTION_QUIET + Duration::from_millis(20))
        .await;
    console.key("y", KeyKind::Press);
    assert!(moving_home(console), "{:?}", console.app.motion_shown());
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn home_over_modbus_shows_moving_until_it_completes_at_rest() {
    let mut console = Console::start_with(away(), false).await;
    home(&mut console).await;
    console.seen.clear();
    console
        .run_until(Duration::from_secs(15), |c| message(c) == "home done")
        .await;
    let before_done = &console.seen[..console.seen.len() - 1];
    assert!(
        before_done.iter().all(|s| *s != MotionShown::Idle),
        "{:?}",
        console.seen
    );
    assert_eq!(console.app.motion_shown(), MotionShown::Idle);
    assert!(!console.moving().await, "done means at rest");
}

/// Step mode, the largest step (100 mm), one press of +X.
fn step_plus_x(console: &mut Console) {
    console.key("t", KeyKind::Press);
    for _ in 0..3 {
        console.key(".", KeyKind::Press);
    }
    assert_eq!(console.app.step().cartesian(), 1000, "100 mm, in tenths");
    console.key("w", KeyKind::Press);
    console.key("w", KeyKind::Release);
}

/// Whether the status bar shows the tracked action `label` (`STEP`, `GOTO beyond`).
fn moving(c: &Console, label: &str) -> bool {
    matches!(&c.app.motion_shown(), MotionShown::Action { label: shown, confirmed: true } if shown == label)
}

/// Runs the action shown as `label` (just started at the tool position `from`, metres) to its
/// end and checks it was a 100 mm move along +X that the arm aborted at J4's limit: the console
/// says so as a failure naming the joint (`verb failed: ...`), never idle or done before, logs
/// nothing OK for it, and then reaches idle truthfully.
async fn assert_aborted_at_j4(console: &mut Console, label: &str, verb: &str, from: [f64; 3]) {
    assert!(moving(console, label), "{:?}", console.app.motion_shown());
    console.seen.clear();
    console
        .run_until(Duration::from_secs(15), |c| !moving(c, label))
        .await;
    assert_eq!(
        message(console),
        format!("{verb} failed: aborted, J4 at its limit"),
        "said {:?}",
        console.said
    );
    // Until and at the failure it never said idle, nor done.
    assert!(
        console.seen.iter().all(|s| *s != MotionShown::Idle),
        "{:?}",
        console.seen
    );
    let done = format!("{verb} done");
    assert!(!console.said.contains(&done), "{:?}", console.said);
    assert!(
        !console.app.log().iter().any(|e| {
            ["step", "cart_move", "move to pose"].contains(&e.name.as_str())
                && e.outcome.contains("OK")
        }),
        "{:?}",
        console.app.log()
    );
    // The arm really moved and really stopped at J4's limit, short of the target.
    let s = console.sim.arm.snapshot().await.expect("sim");
    let j4 = s.joint_position[3];
    assert!((j4 - 147.8).abs() < 0.1, "J4 at {j4}");
    let moved_x = (s.tcp_position[0] - from[0]) * 1000.0;
    assert!(
        (10.0..90.0).contains(&moved_x),
        "moved {moved_x:.1} mm of 100"
    );
    // The STOP it sends is confirmed and the arm seen at rest: idle, truthfully.
    console
        .run_until(Duration::from_secs(5), |c| {
            c.app.motion_shown() == MotionShown::Idle
        })
        .await;
    assert!(!console.moving().await);
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_step_aborted_at_a_joint_limit_is_a_failure_over_modbus_and_over_talos() {
    // Over Talos the step is a Cartesian Move (Discrete) the operator accepts; its end shows
    // in the hardware telemetry (joints at rest, a joint-fault warning).
    for talos in [false, true] {
        let mut console = Console::start_with(step_through_j4_limit(), talos).await;
        let from = console.sim.arm.snapshot().await.expect("sim").tcp_position;
        console.said.clear();
        step_plus_x(&mut console);
        assert_aborted_at_j4(&mut console, "STEP", "step", from).await;
    }
}

/// Over Talos a go-to of a position saved from the arm is a joint-space move, which never
/// passes a limit; one set by coordinates is the operator's straight-line move, as the step
/// above. Over Modbus the console keeps the positions and a go-to is a Move To Pose.
#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_go_to_aborted_at_a_joint_limit_is_a_failure_over_modbus() {
    let mut console = Console::start_with(step_through_j4_limit(), false).await;
    let from = console.sim.arm.snapshot().await.expect("sim").tcp_position;
    // 100 mm along +X, in the tool's current orientation: the step's target.
    let tenths = |m: f64| (m * 10_000.0).round() as i32;
    let mut book = PositionBook::new();
    book.get_or_insert("beyond").cartesian =
        Some([tenths(from[0] + 0.1), tenths(from[1]), tenths(from[2])]);
    console
        .app
        .handle(Input::PositionsLoaded(Ok(book)), Instant::now());
    assert_eq!(console.app.selected_name(), Some("beyond"));
    console.said.clear();
    console.key("o", KeyKind::Press);
    // A question ignores keys for its first moments.
    console
        .run_for(QUESTION_QUIET + Duration::from_millis(20))
        .await;
    console.key("y", KeyKind::Press);
    assert_aborted_at_j4(&mut console, "GOTO beyond", "go to 'beyond'", from).await;
}
