//! The FMI 2.0 Co-Simulation state machine: the states of an instance and, as bit sets,
//! the states in which each function may be called ([`crate::ffi`] checks them).

/// Instance states of the FMI 2.0 Co-Simulation state machine (as bit flags for the
/// table of which function may be called when).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum State {
    Instantiated = 1,
    InitializationMode = 2,
    StepMode = 4,
    Terminated = 8,
    Error = 16,
    Fatal = 32,
}

/// Sets of states in which a function may be called.
pub mod allowed {
    use super::State::*;
    pub const ANY_BUT_FATAL: u8 = Instantiated as u8
        | InitializationMode as u8
        | StepMode as u8
        | Terminated as u8
        | Error as u8;
    pub const INSTANTIATED: u8 = Instantiated as u8;
    pub const INIT: u8 = InitializationMode as u8;
    pub const STEP: u8 = StepMode as u8;
    pub const TERMINATE: u8 = StepMode as u8 | Error as u8;
    pub const GET: u8 = InitializationMode as u8 | StepMode as u8 | Terminated as u8 | Error as u8;
    pub const SET: u8 = Instantiated as u8 | InitializationMode as u8 | StepMode as u8;
    pub const STATE: u8 = ANY_BUT_FATAL;
}

impl State {
    /// Whether the state is one of the set `allowed` (see [`allowed`]).
    pub fn in_set(self, allowed: u8) -> bool {
        self as u8 & allowed != 0
    }
}
