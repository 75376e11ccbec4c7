//! # core-algo
//!
//! Every decision an e-puck robot makes, as pure `no_std` code without
//! allocation: the same functions run on the e-puck2 (STM32F407), in the
//! simulator on the host and on the phone side on behalf of a robot that
//! cannot run them itself. Nothing here performs I/O; callers feed events in
//! and take decisions out, in the manner of smoltcp.
//!
//! One coordinate frame everywhere: x grows east, y grows north (see
//! [`geometry`]).
#![no_std]
#![forbid(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::todo,
        clippy::unimplemented,
        clippy::unreachable
    )
)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod agent;
pub mod behaviour;
pub mod control;
pub mod explore;
pub mod geometry;
pub mod localize;
pub mod map;
pub mod path;
pub mod protocol;
pub mod team;
pub mod timing;
