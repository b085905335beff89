//! Which tock-CSP semantics a check or an export follows (semantics.md
//! §2). The native checker and the CSPm export both read it here, so that
//! neither depends on the other for it.

/// Which tock-CSP semantics to follow.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Profile {
    /// What RoboTool 3 generates (the default).
    #[default]
    RoboTool3,
    /// The definitions of Cavalcanti et al., *Verified simulation for
    /// robotics*, SCP 2019.
    Paper2019,
}

impl Profile {
    /// The name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Profile::RoboTool3 => "robotool3",
            Profile::Paper2019 => "paper2019",
        }
    }
}
