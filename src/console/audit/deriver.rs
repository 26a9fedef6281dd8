//! Audit records from what flows between app and driver. Pure: each call takes its time.

use std::collections::BTreeMap;
use std::time::{Duration, SystemTime};

use super::{AuditEvent, AuditRecord};
use crate::console::app::tool_position;
use crate::console::coords::describe_motion;
use crate::console::positions::PositionBook;
use crate::kortex::arm_state::fault_reason;
use crate::kortex::{CodeName, ReferenceFrame};
use crate::link::interface::{
    ArmCommand, ArmError, ArmEvent, GuardStatus, JogMotion, LinkStatus, StepMove,
};
use crate::link::speed::{INITIAL_SPEED, SpeedCap, is_settable};

/// What the deriver remembers between calls, to turn a stream into starts and stops.
#[derive(Debug, Clone)]
pub struct AuditDeriver {
    /// The speed cap the driver keeps to: what a percentage is in mm/s and deg/s.
    cap: SpeedCap,
    /// Whether reference frames apply (Modbus jogs): then jog starts name theirs.
    frames: bool,
    /// Positions live on a Talos operator (its commands are recorded); else the book's saves are.
    positions_on_operator: bool,
    jog: Option<(JogMotion, SystemTime)>,
    /// The speed the next command runs at (commands run in order).
    speed: u8,
    /// The link status last recorded; `Connecting` records nothing.
    link: Option<LinkStatus>,
    stale: bool,
    fault: Option<String>,
    /// The local book as last saved or loaded: name to coordinates (tenths of mm).
    book: BTreeMap<String, Option<[i32; 3]>>,
    /// The tool's latest position (0.1 mm): where an operator saves a position.
    tool: Option<[i32; 3]>,
    /// The cap watch's stops already recorded.
    cap_stops: u64,
}

impl AuditDeriver {
    /// `max_jog_speed` in m/s.
    ///
    /// # Panics
    /// On a `max_jog_speed` [`SpeedCap::new`] refuses (the front ends refuse it first).
    pub fn new(max_jog_speed: f64, frames: bool, positions_on_operator: bool) -> AuditDeriver {
        AuditDeriver {
            cap: SpeedCap::configured(max_jog_speed),
            frames,
            positions_on_operator,
            jog: None,
            speed: INITIAL_SPEED,
            link: None,
            stale: false,
            fault: None,
            book: BTreeMap::new(),
            tool: None,
            cap_stops: 0,
        }
    }

    fn speed_mm_s(&self, percent: u8) -> f64 {
        round_tenth(self.cap.tool_speed_mm_s(percent))
    }

    /// A jog's rate cap at `percent`: a tool turn's in deg/s, any other's in mm/s.
    fn jog_rate(&self, motion: &JogMotion, percent: u8) -> (Option<f64>, Option<f64>) {
        match motion {
            JogMotion::Orientation { .. } => (
                None,
                Some(round_tenth(f64::from(self.cap.turn_rate(percent)))),
            ),
            _ => (Some(self.speed_mm_s(percent)), None),
        }
    }

    /// A command sent to the driver. `book` and `selected` name a go-to's position (a Modbus move
    /// carries only a pose); `frame` is the jog frame (`App::frame`).
    pub fn command(
        &mut self,
        command: &ArmCommand,
        book: &PositionBook,
        selected: Option<&str>,
        frame: ReferenceFrame,
        at: SystemTime,
    ) -> Vec<AuditRecord> {
        let name = go_to_name(command, book, selected);
        self.command_named(command, name, frame, at)
    }

    /// [`Self::command`] with a go-to's position already named ([`go_to_name`]).
    pub fn command_named(
        &mut self,
        command: &ArmCommand,
        go_to_name: Option<String>,
        frame: ReferenceFrame,
        at: SystemTime,
    ) -> Vec<AuditRecord> {
        let speed_percent = self.speed;
        let speed_mm_s = self.speed_mm_s(speed_percent);
        // Every stop ends the jog being recorded.
        let stopped_jog = if command.is_stop() {
            self.jog.take()
        } else {
            None
        };
        let event = match command {
            ArmCommand::Jog(motion) => {
                let (speed_mm_s, speed_deg_s) = self.jog_rate(motion, speed_percent);
                let axis = describe_motion(*motion);
                // A turn always goes over Modbus, in the chosen frame.
                let framed = matches!(motion, JogMotion::Orientation { .. })
                    || (self.frames && matches!(motion, JogMotion::Cartesian { .. }));
                match self.jog.replace((*motion, at)) {
                    // A refresh of the same jog or a change of direction: it runs since it started.
                    Some((running, since)) => {
                        self.jog = Some((*motion, since));
                        (running != *motion).then(|| AuditEvent::JogChange {
                            axis,
                            from: describe_motion(running),
                            speed_percent,
                            speed_mm_s,
                            speed_deg_s,
                        })
                    }
                    None => Some(AuditEvent::JogStart {
                        axis,
                        frame: framed.then(|| frame.key().to_string()),
                        speed_percent,
                        speed_mm_s,
                        speed_deg_s,
                    }),
                }
            }
            ArmCommand::Stop => Some(match stopped_jog {
                Some((motion, since)) => AuditEvent::JogStop {
                    axis: describe_motion(motion),
                    duration_ms: millis(at.duration_since(since).unwrap_or_default()),
                },
                None => AuditEvent::Stop,
            }),
            ArmCommand::QuickStop => Some(AuditEvent::QuickStop),
            ArmCommand::Step(step) => Some(step_event(*step, speed_percent, speed_mm_s)),
            ArmCommand::MoveToPose(pose) => Some(AuditEvent::GoTo {
                name: go_to_name,
                position_mm: Some(
                    // To a tenth of a millimetre: an f32 pose in metres has no more to say.
                    [pose.x, pose.y, pose.z].map(|v| round_tenth(f64::from(v) * 1000.0)),
                ),
                speed_percent,
                speed_mm_s,
            }),
            ArmCommand::GoToPosition { name } => Some(AuditEvent::GoTo {
                name: Some(name.clone()),
                position_mm: None,
                speed_percent,
                speed_mm_s,
            }),
            ArmCommand::Home => Some(AuditEvent::Home {
                speed_percent,
                speed_mm_s,
            }),
            ArmCommand::StartStored(stored) => Some(AuditEvent::Stored {
                kind: stored.motion.name().to_string(),
                id: stored.id,
                speed_percent,
                speed_mm_s,
            }),
            ArmCommand::SetSpeed(percent) => {
                if is_settable(*percent) {
                    self.speed = *percent;
                }
                Some(AuditEvent::Speed {
                    percent: *percent,
                    mm_s: self.speed_mm_s(*percent),
                })
            }
            ArmCommand::FenceSpeed(permille) => Some(AuditEvent::FenceSpeed {
                permille: *permille,
                mm_s: round_tenth(
                    self.cap.tool_speed_mm_s(speed_percent) * f64::from(*permille) / 1000.0,
                ),
            }),
            ArmCommand::SetFrame(frame) => Some(AuditEvent::Frame {
                frame: frame.key().to_string(),
            }),
            ArmCommand::FaultReset => Some(AuditEvent::FaultReset),
            ArmCommand::SavePosition {
                name,
                anchor,
                parent,
            } => Some(AuditEvent::Save {
                name: name.clone(),
                // The operator saves where the arm is: the telemetry's tool position.
                position_mm: self.tool.map(tenths_mm),
                polar: None,
                anchor: *anchor,
                parent: parent.clone(),
            }),
            ArmCommand::SetCartesianPosition { name, x, y, z } => Some(AuditEvent::Save {
                name: name.clone(),
                position_mm: Some(tenths_mm([*x, *y, *z])),
                polar: None,
                anchor: false,
                parent: None,
            }),
            ArmCommand::SetPolarPosition {
                name,
                delta,
                azimuth,
                radius,
            } => Some(AuditEvent::Save {
                name: name.clone(),
                position_mm: None,
                polar: Some(tenths_mm([*delta, *azimuth, *radius])),
                anchor: false,
                parent: None,
            }),
            ArmCommand::DeletePosition { name } => Some(AuditEvent::Delete { name: name.clone() }),
            // Reading a position moves nothing and changes nothing.
            ArmCommand::GetPosition { .. } => None,
        };
        event
            .into_iter()
            .map(|event| AuditRecord::new(at, event))
            .collect()
    }

    /// An event the driver reported.
    pub fn arm_event(&mut self, event: &ArmEvent, at: SystemTime) -> Vec<AuditRecord> {
        let event = match event {
            ArmEvent::Status(status) => self.link_status(status),
            ArmEvent::Speed(percent) => {
                self.speed = *percent;
                None
            }
            ArmEvent::Telemetry(telemetry) => {
                self.tool = tool_position(telemetry);
                let reason = fault_reason(telemetry);
                if reason == self.fault {
                    None
                } else {
                    self.fault = reason.clone();
                    Some(match reason {
                        Some(reason) => AuditEvent::Fault { reason },
                        None => AuditEvent::FaultCleared,
                    })
                }
            }
            // Reported as a failed jog (the console latches held keys as for one), whatever ran.
            ArmEvent::Failed {
                error: error @ (ArmError::GuardStoppedArm(_) | ArmError::GuardStopFailed(_)),
                ..
            } => Some(AuditEvent::GuardStop {
                error: error.to_string(),
            }),
            ArmEvent::Failed { command, error } => Some(AuditEvent::CommandFailed {
                command: command.to_string(),
                error: error.to_string(),
            }),
            ArmEvent::StopUnconfirmed { reason } => Some(AuditEvent::StopUnconfirmed {
                reason: reason.clone(),
            }),
            ArmEvent::Guard(GuardStatus::Down { reason }) => Some(AuditEvent::GuardDown {
                reason: reason.clone(),
            }),
            ArmEvent::Notice(text) => Some(AuditEvent::DriverNotice { text: text.clone() }),
            _ => None,
        };
        event
            .into_iter()
            .map(|event| AuditRecord::new(at, event))
            .collect()
    }

    fn link_status(&mut self, status: &LinkStatus) -> Option<AuditEvent> {
        let event = match status {
            LinkStatus::Connecting => return None,
            _ if self.link.as_ref() == Some(status) => return None,
            LinkStatus::Up { description } => AuditEvent::LinkUp {
                description: description.clone(),
            },
            LinkStatus::Down { reason } => AuditEvent::LinkDown {
                reason: reason.clone(),
            },
        };
        self.link = Some(status.clone());
        self.stale = false;
        Some(event)
    }

    /// The link's staleness after an input (`App::link_stale`): recorded when it turns.
    pub fn link_stale(&mut self, stale: Option<Duration>, at: SystemTime) -> Vec<AuditRecord> {
        let event = match (stale, self.stale) {
            (Some(silent), false) => AuditEvent::LinkStale {
                silent_ms: millis(silent),
            },
            (None, true) => AuditEvent::LinkFresh,
            _ => return Vec::new(),
        };
        self.stale = stale.is_some();
        vec![AuditRecord::new(at, event)]
    }

    /// How many of the cap watch's stops have been recorded.
    pub fn cap_stops_recorded(&self) -> u64 {
        self.cap_stops
    }

    /// The cap watch's stops after an input (`CapWatch::stops`): each new one recorded once.
    pub fn cap_stops(
        &mut self,
        (stops, reason): (u64, Option<&str>),
        at: SystemTime,
    ) -> Vec<AuditRecord> {
        if stops == self.cap_stops {
            return Vec::new();
        }
        self.cap_stops = stops;
        let reason = reason.unwrap_or_default().to_string();
        vec![AuditRecord::new(at, AuditEvent::OverCap { reason })]
    }

    /// The book as read from its file: the baseline later saves are compared with.
    pub fn book_loaded(&mut self, book: &PositionBook) {
        self.book = coordinates(book);
    }

    /// The book about to be written. Over Modbus it is the only store, so its changes are the
    /// technician's saves and deletes; with an operator, its commands are recorded instead.
    pub fn book_saved(&mut self, book: &PositionBook, at: SystemTime) -> Vec<AuditRecord> {
        let now = coordinates(book);
        let before = std::mem::replace(&mut self.book, now);
        if self.positions_on_operator {
            return Vec::new();
        }
        let deleted = before
            .keys()
            .filter(|name| !self.book.contains_key(*name))
            .map(|name| AuditEvent::Delete { name: name.clone() });
        let saved = self
            .book
            .iter()
            .filter(|(name, c)| before.get(*name) != Some(c))
            .map(|(name, c)| {
                let entry = book.get(name);
                AuditEvent::Save {
                    name: name.clone(),
                    position_mm: c.map(tenths_mm),
                    polar: None,
                    anchor: entry.is_some_and(|e| e.anchor),
                    parent: entry.and_then(|e| e.parent.clone()),
                }
            });
        deleted
            .chain(saved)
            .map(|event| AuditRecord::new(at, event))
            .collect()
    }
}

fn coordinates(book: &PositionBook) -> BTreeMap<String, Option<[i32; 3]>> {
    book.entries()
        .map(|(name, entry)| (name.to_string(), entry.cartesian))
        .collect()
}

fn step_event(step: StepMove, speed_percent: u8, speed_mm_s: f64) -> AuditEvent {
    let sign = |v: i32| v.signum() as i8;
    match step {
        StepMove::Cartesian { dx, dy, dz } => AuditEvent::Step {
            axis: describe_motion(JogMotion::Cartesian {
                x: sign(dx),
                y: sign(dy),
                z: sign(dz),
            }),
            delta_mm: Some(tenths_mm([dx, dy, dz])),
            delta_deg: None,
            speed_percent,
            speed_mm_s,
        },
        StepMove::Polar { azimuth, altitude } => AuditEvent::Step {
            axis: describe_motion(JogMotion::Polar {
                azimuth: sign(azimuth),
                altitude: sign(altitude),
            }),
            delta_mm: None,
            delta_deg: Some([azimuth, altitude]),
            speed_percent,
            speed_mm_s,
        },
    }
}

/// The book's name for where a move to a pose goes (a Modbus go-to carries no name): the selected
/// position if it is there, else the first that is.
pub fn go_to_name(
    command: &ArmCommand,
    book: &PositionBook,
    selected: Option<&str>,
) -> Option<String> {
    let ArmCommand::MoveToPose(pose) = command else {
        return None;
    };
    let target = [pose.x, pose.y, pose.z].map(|v| (f64::from(v) * 10_000.0).round() as i32);
    let at_pose = |name: &str| book.get(name).and_then(|e| e.cartesian) == Some(target);
    selected
        .filter(|name| at_pose(name))
        .or_else(|| book.names().find(|name| at_pose(name)))
        .map(str::to_string)
}

/// Tenths (of mm or of degrees) as decimals.
fn tenths_mm(v: [i32; 3]) -> [f64; 3] {
    v.map(|t| f64::from(t) / 10.0)
}

/// To a tenth (of mm/s, of deg/s).
fn round_tenth(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}

fn millis(d: Duration) -> u64 {
    u64::try_from(d.as_millis()).unwrap_or(u64::MAX)
}
