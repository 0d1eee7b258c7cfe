//! The command line's tests, one module per concern, linked into one test binary.

mod budget_cli;
mod element_cli;
mod ensemble_cli;
mod golden;
mod hostile_scenes;
mod ipc;
mod outputs;
