//! The wire protocol between robots and the phone side.
//!
//! Built in layers, each a pure function or state machine without I/O, in
//! the manner of smoltcp, so that the firmware, the simulator and the phone
//! side run the same code and the host can test and fuzz it:
//!
//! * [`message`]: the typed [`Message`]s and their postcard encoding;
//! * [`frame`]: one checked [`Frame`] (header, message, CRC-32C, COBS);
//! * [`stream`]: the [`StreamDecoder`] that cuts a byte stream into frames;
//! * [`link`]: the reliable [`Link`] (acknowledgements, retransmission,
//!   in-order delivery, heartbeat, link loss and resynchronisation);
//! * [`resync`]: streaming the map a reconnected robot missed;
//! * [`legacy`]: the 32-byte protocol of the 2010 firmware, to drive an
//!   original e-puck.
//!
//! Nothing here panics on any input; every decoder is fuzzed (`fuzz/`).
//! The byte layouts are documented in `docs/protocol.md`.

pub mod frame;
pub mod legacy;
pub mod link;
pub mod message;
pub mod resync;
pub mod stream;

pub use frame::{Body, Frame, FrameError, Header, MAX_FRAME_LEN, PHONE};

pub use link::{Event, Link, LinkConfig, SendError};
pub use message::{Broadcast, Message, Pose};
pub use stream::{Stats, StreamDecoder};

#[cfg(test)]
mod link_tests;
#[cfg(test)]
mod tests;
