//! What the driver says about the link and the arm, and what the console keeps of it.

use std::time::Duration;

use super::super::cap_watch::CapWatch;
use super::super::history::History;
use super::super::other_client;
use super::super::trail::ToolTrail;
use crate::kortex::{ReferenceFrame, Telemetry};
use crate::link::interface::{GuardStatus, LinkStatus};

/// What the driver says about the link and the arm, and what the console keeps of it.
#[derive(Debug, Clone)]
pub(in crate::console::app) struct Arm {
    pub(in crate::console::app) link: LinkStatus,
    pub(in crate::console::app) telemetry: Option<Telemetry>,
    pub(in crate::console::app) latency: Option<Duration>,
    pub(in crate::console::app) speed: Option<u8>,
    pub(in crate::console::app) frame: ReferenceFrame,
    /// The stop guard's state, once the driver says one is required (Modbus motion).
    pub(in crate::console::app) guard: Option<GuardStatus>,
    /// The last 30 s of telemetry, for the history panel.
    pub(in crate::console::app) history: History,
    /// The tool point's recent path, for the arm view.
    pub(in crate::console::app) trail: ToolTrail,
    /// The speed cap as the telemetry shows it kept.
    pub(in crate::console::app) cap_watch: CapWatch,
    /// Other clients on the same arm: their stops and motions (see `other_client`).
    pub(in crate::console::app) others: other_client::OtherClients,
}

impl Default for Arm {
    fn default() -> Arm {
        Arm {
            link: LinkStatus::Connecting,
            telemetry: None,
            latency: None,
            speed: None,
            frame: ReferenceFrame::Base,
            guard: None,
            history: History::default(),
            trail: ToolTrail::default(),
            cap_watch: CapWatch::default(),
            others: other_client::OtherClients::default(),
        }
    }
}

