//! Each link's state as the driver knows it, and the one status shown for them.

use super::DriverConfig;
use super::connect::ConnectError;
use crate::link::interface::LinkStatus;
use crate::link::modbus::ModbusConfig;

#[derive(Debug, Clone, PartialEq, Default)]
pub enum LinkState {
    /// Not connected yet, and no attempt has failed.
    #[default]
    Connecting,
    /// Connected: the words the status bar shows for it.
    Up { description: String },
    /// Not connected, and why.
    Lost(LostReason),
}

/// Why a link is not connected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LostReason {
    /// A connect or handshake failed.
    #[error("{0}")]
    ConnectFailed(ConnectError),
    /// The Talos link was up and dropped.
    #[error("talos: {0}")]
    TalosDisconnected(String),
    /// The Modbus link was up and dropped.
    #[error("modbus: {0}")]
    ModbusDisconnected(String),
}

/// How the status bar names a Modbus link that is up.
pub fn modbus_description(config: &ModbusConfig) -> String {
    format!("modbus {} unit {}", config.addr, config.unit)
}

/// Both links' states; an unconfigured one stays [`LinkState::Connecting`], left out of the status.
#[derive(Default)]
pub struct Links {
    pub talos: LinkState,
    pub modbus: LinkState,
}

impl Links {
    /// A failed connect (a lost link keeps its first reason). Returns whether the state changed.
    pub fn connect_failed(state: &mut LinkState, error: ConnectError) -> bool {
        if matches!(state, LinkState::Lost(_)) {
            return false;
        }
        *state = LinkState::Lost(LostReason::ConnectFailed(error));
        true
    }

    /// For the status bar: connecting or lost if any wanted link is (its reason), else up.
    pub fn status(&self, config: &DriverConfig) -> LinkStatus {
        let parts = [
            (config.talos.is_some(), &self.talos),
            (config.modbus.is_some(), &self.modbus),
        ];
        let mut up = Vec::new();
        for (_, state) in parts.into_iter().filter(|(wanted, _)| *wanted) {
            match state {
                LinkState::Connecting => return LinkStatus::Connecting,
                LinkState::Lost(reason) => {
                    return LinkStatus::Down {
                        reason: reason.to_string(),
                    };
                }
                LinkState::Up { description } => up.push(description.clone()),
            }
        }
        if up.is_empty() {
            return LinkStatus::Down {
                reason: "no link configured".into(),
            };
        }
        LinkStatus::Up {
            description: up.join(" + "),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::link::talos::TalosConfig;

    fn both() -> DriverConfig {
        DriverConfig::new(
            Some(TalosConfig::new("127.0.0.1:1")),
            Some(ModbusConfig::new("127.0.0.1:2")),
        )
    }

    #[test]
    fn both_links_show_up_only_when_both_are_and_a_lost_one_says_which() {
        let config = both();
        let mut links = Links::default();
        assert_eq!(links.status(&config), LinkStatus::Connecting);
        links.talos = LinkState::Up {
            description: "talos x".into(),
        };
        assert_eq!(links.status(&config), LinkStatus::Connecting);
        links.modbus = LinkState::Up {
            description: modbus_description(config.modbus.as_ref().unwrap()),
        };
        assert_eq!(
            links.status(&config),
            LinkStatus::Up {
                description: "talos x + modbus 127.0.0.1:2 unit 1".into()
            }
        );
        links.modbus = LinkState::Lost(LostReason::ModbusDisconnected("reset".into()));
        assert_eq!(
            links.status(&config),
            LinkStatus::Down {
                reason: "modbus: reset".into()
            }
        );
    }

    #[test]
    fn a_failed_reconnect_keeps_the_reason_the_link_went_down_with() {
        let mut state = LinkState::Connecting;
        let refused = || ConnectError::Handshake("refused".into());
        assert!(Links::connect_failed(&mut state, refused()));
        assert!(!Links::connect_failed(
            &mut state,
            ConnectError::Handshake("again".into())
        ));
        assert_eq!(state, LinkState::Lost(LostReason::ConnectFailed(refused())));
        let mut lost = LinkState::Lost(LostReason::TalosDisconnected("eof".into()));
        assert!(!Links::connect_failed(&mut lost, refused()));
    }
}
