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
    /// `fmi2Terminate`: from step mode only (FMI 2.0 §4.2.4: stepComplete, stepFailed,
    /// stepCanceled); the error state is left by `fmi2SetFMUstate` or `fmi2Reset`.
    pub const TERMINATE: u8 = StepMode as u8;
    /// Value getters (`fmi2GetReal`, …): not in the error state, where no output is
    /// valid (docs/fmu.md, *The error state*).
    pub const GET: u8 = InitializationMode as u8 | StepMode as u8 | Terminated as u8;
    /// Status getters (`fmi2GetRealStatus`, …): in the error state too, so a master
    /// can ask for the last successful time.
    pub const STATUS: u8 = GET | Error as u8;
    pub const SET: u8 = Instantiated as u8 | InitializationMode as u8 | StepMode as u8;
    pub const STATE: u8 = ANY_BUT_FATAL;
}

impl State {
    /// The state of bit `b` (a serialised state's byte), if it is one.
    pub fn from_bit(b: u8) -> Option<State> {
        [
            State::Instantiated,
            State::InitializationMode,
            State::StepMode,
            State::Terminated,
            State::Error,
            State::Fatal,
        ]
        .into_iter()
        .find(|s| *s as u8 == b)
    }

    /// Whether the state is one of the set `allowed` (see [`allowed`]).
    pub fn in_set(self, allowed: u8) -> bool {
        self as u8 & allowed != 0
    }
}

/// An instance's place in the state machine as a state carries it: the state, and why
/// the instance is in the error state (the logged message of the call that failed).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Place {
    pub state: State,
    pub failure: Option<String>,
}
