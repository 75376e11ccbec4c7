//! The reliable link: one endpoint of a point-to-point connection.
//!
//! A pure state machine in the manner of smoltcp's sockets: the caller feeds
//! received bytes with [`Link::on_bytes`], asks for bytes to send with
//! [`Link::poll_transmit`], drives the timers with [`Link::tick`] and takes
//! what happened from [`Link::poll_event`]. Time is passed in as `u32`
//! milliseconds and only ever compared by wrapping difference, so the clock
//! may start anywhere and wrap. The same code runs in the firmware (UART
//! interrupt and a periodic task) and on the phone side (one per robot).
//!
//! What the link guarantees for messages sent with [`Link::send`]:
//! delivered once, in order, as long as the peer's session lasts. How:
//!
//! * **Sequence numbers, cumulative and selective acknowledgements.** Every
//!   data frame has a 16-bit sequence number; every frame carries the number
//!   of the next data frame its sender expects (`ack`) and a bit map of the
//!   [`WINDOW`] frames after it that already arrived (`sack`). Selective
//!   repeat: the receiver buffers frames that arrive early and delivers them
//!   once the gap is filled; frames it has seen are dropped, which
//!   suppresses duplicates. A lost frame thus costs one retransmission, not
//!   a window's worth (go-back-N, the first version of this link, managed
//!   only 4 messages/s over the 20 %-loss test channel).
//! * **Retransmission.** When the oldest unacknowledged frame is older than
//!   the timeout, every frame not selectively acknowledged is sent again;
//!   when two later frames are acknowledged while the oldest is not, it is
//!   resent at once (fast retransmit). The timeout doubles with each
//!   consecutive failure, up to 16×, so a dead link is not flooded. After `max_retries` failures the link reports
//!   [`Event::LinkLost`], but keeps the queue and keeps trying: when the peer
//!   answers again the queue drains and [`Event::LinkUp`] is reported.
//! * **Heartbeat.** An endpoint that sent nothing for `heartbeat_ms` sends
//!   an empty [`Body::Ack`]; one that heard nothing for `link_timeout_ms`
//!   reports [`Event::LinkLost`].
//! * **Sessions.** Each endpoint starts from a random `u32` nonce (the
//!   STM32's RNG, or the host's): its low byte is the session number (never
//!   0), the next two bytes the first sequence number. A [`Body::Sync`]
//!   tells the peer the session and first sequence number; the peer echoes
//!   the session in every header (`peer_session`), and data is sent only
//!   while it does. When a robot reboots, its new session makes the phone
//!   report [`Event::PeerRestarted`] instead of mistaking the new sequence
//!   numbers for duplicates; the robot then asks for the map it missed with
//!   [`Message::ResyncRequest`] (see [`super::resync`]). Should a reboot
//!   draw the same session byte (1 in 255), the Sync still gives it away:
//!   within one session a Sync's sequence number is never more than
//!   [`WINDOW`] behind what the receiver expects, and a random first
//!   number almost never is.
//!
//! Memory: [`WINDOW`] queued and [`WINDOW`] early-arrived messages,
//! [`EVENTS`] pending events, one best-effort message and one stream
//! decoder, about 3.3 KiB in all (a test checks the bound).

use heapless::Deque;

use super::frame::{Body, Frame, Header};
use super::message::Message;
use super::stream::{Stats, StreamDecoder};
use crate::team::RobotId;

/// Reliable messages queued or in flight per link.
///
/// Sixteen keep a link that loses 30 % of its frames streaming at 24
/// messages/s (the relay load of a team of six, see `docs/protocol.md`):
/// a lost frame holds up the window for a timeout, and the window must not
/// run dry meanwhile. It is also the width of the `sack` bit map.
pub const WINDOW: usize = 16;

/// Events buffered until the application takes them. A data frame that
/// finds this queue full is not acknowledged and so comes again later.
pub const EVENTS: usize = 8;

/// Timing of a link, in milliseconds.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub struct LinkConfig {
    /// Retransmission timeout for the first attempt. A 20-byte frame takes
    /// 1.7 ms at 115 200 baud; Bluetooth SPP adds tens of ms of latency.
    pub rto_ms: u32,
    /// Consecutive timeouts of one frame before [`Event::LinkLost`].
    pub max_retries: u8,
    /// Idle time after which a heartbeat is sent.
    pub heartbeat_ms: u32,
    /// Silence after which the link is reported lost.
    pub link_timeout_ms: u32,
}

impl Default for LinkConfig {
    /// 200 ms timeout; loss after 6 retries, i.e. at the 7th consecutive
    /// timeout, 12.6 s with the back-off (a peer that still sends heartbeats
    /// but acknowledges nothing); a heartbeat every 500 ms; loss after 2 s
    /// of silence (four missed heartbeats), which usually reports first.
    fn default() -> Self {
        LinkConfig {
            rto_ms: 200,
            max_retries: 6,
            heartbeat_ms: 500,
            link_timeout_ms: 2000,
        }
    }
}

/// Something the application must know about.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Event {
    /// A message from the peer.
    Received {
        /// Who sent it (the frame's sender).
        from: RobotId,
        /// The sequence number of a reliable message (answer a command with
        /// `Message::Ack { command: seq }`); `None` for a best-effort one.
        seq: Option<u16>,
        /// The message.
        message: Message,
    },
    /// The peer is heard again (also at the first frame ever).
    LinkUp,
    /// The peer fell silent or stopped acknowledging.
    LinkLost,
    /// The peer started a new session (it rebooted or reset its link): it
    /// has forgotten everything, so its state must be resent.
    PeerRestarted,
}

/// Why a message was not queued.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
pub enum SendError {
    /// [`WINDOW`] reliable messages are already waiting; try again after
    /// the peer acknowledged some.
    QueueFull,
}

/// A reliable message waiting for its acknowledgement.
#[derive(Clone, Debug)]
struct Pending {
    seq: u16,
    message: Message,
    /// When it was last sent; `None`: (re)send it at the next chance.
    sent_at: Option<u32>,
    /// Whether it was sent before (for the retransmission counter).
    sent_once: bool,
    /// The peer reported it received (selective acknowledgement).
    sacked: bool,
}

/// Milliseconds from `since` to `now`, correct across a wrap of the clock.
const fn elapsed(now: u32, since: u32) -> u32 {
    now.wrapping_sub(since)
}

/// One endpoint of a reliable link. See the module documentation.
#[derive(Clone, Debug)]
pub struct Link {
    config: LinkConfig,
    local: RobotId,
    session: u8,
    // Sending side.
    next_seq: u16,
    queue: Deque<Pending, WINDOW>,
    retries: u8,
    datagram: Option<Message>,
    peer_synced: bool,
    sync_sent_at: Option<u32>,
    // Receiving side.
    peer: Option<RobotId>,
    peer_session: u8,
    rx_next: u16,
    /// Early data frames: slot `seq % WINDOW` holds frame `seq`.
    early: [Option<(u16, Message)>; WINDOW],
    ack_due: bool,
    decoder: StreamDecoder,
    events: Deque<Event, EVENTS>,
    // Liveness.
    up: bool,
    last_rx: Option<u32>,
    last_tx: Option<u32>,
    retransmissions: u32,
    tx_frames: u32,
    tx_bytes: u32,
}

impl Link {
    /// A new endpoint with address `local`, started from `nonce`: a fresh
    /// random number at every start (see the module documentation). Its low
    /// byte is the session (0 is reserved and becomes 1), bits 8..24 the
    /// first sequence number. It starts by sending a Sync.
    pub fn new(config: LinkConfig, local: RobotId, nonce: u32) -> Self {
        let [session, s0, s1, _] = nonce.to_le_bytes();
        Link {
            config,
            local,
            session: session.max(1),
            next_seq: u16::from_le_bytes([s0, s1]),
            queue: Deque::new(),
            retries: 0,
            datagram: None,
            peer_synced: false,
            sync_sent_at: None,
            peer: None,
            peer_session: 0,
            rx_next: 0,
            early: [const { None }; WINDOW],
            ack_due: false,
            decoder: StreamDecoder::new(),
            events: Deque::new(),
            up: false,
            last_rx: None,
            last_tx: None,
            retransmissions: 0,
            tx_frames: 0,
            tx_bytes: 0,
        }
    }

    /// Queues a message for reliable, in-order delivery and returns its
    /// sequence number (the peer answers commands with it).
    pub fn send(&mut self, message: Message) -> Result<u16, SendError> {
        let seq = self.next_seq;
        self.queue
            .push_back(Pending {
                seq,
                message,
                sent_at: None,
                sent_once: false,
                sacked: false,
            })
            .map_err(|_| SendError::QueueFull)?;
        self.next_seq = seq.wrapping_add(1);
        Ok(seq)
    }

    /// Sends `message` the way its kind asks for ([`Message::is_reliable`]):
    /// commands and events reliably (returns the sequence number), status
    /// and log lines best-effort (returns `None`).
    pub fn submit(&mut self, message: Message) -> Result<Option<u16>, SendError> {
        if message.is_reliable() {
            self.send(message).map(Some)
        } else {
            self.send_datagram(message);
            Ok(None)
        }
    }

    /// Sends a message best-effort at the next chance. Only the newest one
    /// is kept: a status replaces an older status that was not yet sent.
    pub fn send_datagram(&mut self, message: Message) {
        self.datagram = Some(message);
    }

    /// Feeds bytes received from the peer, in any chunking.
    pub fn on_bytes(&mut self, now: u32, mut bytes: &[u8]) {
        while let Some(r) = self.decoder.next_frame(&mut bytes) {
            if let Ok(frame) = r {
                self.on_frame(now, frame);
            }
        }
    }

    /// Handles one decoded frame (for transports that frame by themselves).
    pub fn on_frame(&mut self, now: u32, frame: Frame) {
        let h = frame.header;
        if h.session == 0 {
            return;
        }
        self.last_rx = Some(now);
        self.peer = Some(h.sender);
        if !self.up {
            self.up = true;
            self.push_event(Event::LinkUp);
        }
        if h.peer_session == self.session {
            self.peer_synced = true;
            self.on_ack(now, h.ack, h.sack);
        } else {
            // The peer does not know our session (it restarted, or never
            // heard our Sync): its selective acks no longer hold.
            self.peer_synced = false;
            for p in self.queue.iter_mut() {
                p.sacked = false;
            }
        }
        match frame.body {
            Body::Sync => {
                // A Sync of the current peer session is never more than a
                // window behind `rx_next`; otherwise the peer restarted and
                // happened to draw the same session byte.
                let behind = usize::from(self.rx_next.wrapping_sub(h.seq));
                if h.session != self.peer_session || behind > WINDOW {
                    if self.peer_session != 0 {
                        self.push_event(Event::PeerRestarted);
                    }
                    self.peer_session = h.session;
                    self.rx_next = h.seq;
                    self.early = [const { None }; WINDOW];
                }
                self.ack_due = true;
            }
            Body::Data(message) => {
                let ahead = usize::from(h.seq.wrapping_sub(self.rx_next));
                if h.session == self.peer_session && ahead < WINDOW {
                    if let Some(slot) = self.early.get_mut(usize::from(h.seq) % WINDOW) {
                        if slot.is_none() {
                            *slot = Some((h.seq, message));
                        }
                    }
                    self.deliver();
                }
                self.ack_due = true;
            }
            Body::Datagram(message) => self.push_event(Event::Received {
                from: h.sender,
                seq: None,
                message,
            }),
            Body::Ack => {}
        }
    }

    /// Moves buffered frames that are next in order to the event queue,
    /// as far as it has room.
    fn deliver(&mut self) {
        let from = self.peer.unwrap_or(RobotId::NONE);
        while !self.events.is_full() {
            let Some(slot) = self.early.get_mut(usize::from(self.rx_next) % WINDOW) else {
                return;
            };
            match slot.take() {
                Some((seq, message)) if seq == self.rx_next => {
                    self.push_event(Event::Received {
                        from,
                        seq: Some(seq),
                        message,
                    });
                    self.rx_next = self.rx_next.wrapping_add(1);
                }
                other => {
                    *slot = other;
                    return;
                }
            }
        }
    }

    /// The selective-acknowledgement bits for the frames after `rx_next`.
    fn sack(&self) -> u16 {
        let mut bits = 0u16;
        for i in 0..WINDOW.min(16) {
            let seq = self.rx_next.wrapping_add(1).wrapping_add(i as u16);
            if let Some(Some((s, _))) = self.early.get(usize::from(seq) % WINDOW) {
                if *s == seq {
                    bits |= 1 << i;
                }
            }
        }
        bits
    }

    fn on_ack(&mut self, now: u32, ack: u16, sack: u16) {
        let Some(front) = self.queue.front() else {
            return;
        };
        let acked = ack.wrapping_sub(front.seq);
        let in_flight = self.next_seq.wrapping_sub(front.seq);
        if acked > in_flight {
            return;
        }
        for _ in 0..acked {
            self.queue.pop_front();
        }
        if acked > 0 {
            self.retries = 0;
        }
        let mut later = 0;
        for p in self.queue.iter_mut() {
            let bit = p.seq.wrapping_sub(ack).wrapping_sub(1);
            if bit < 16 && sack & (1 << bit) != 0 {
                p.sacked = true;
                later += 1;
            }
        }
        // Two later frames arrived but not the oldest: it is lost, not late.
        // Resend it at once, at most every quarter timeout.
        let guard = self.config.rto_ms / 4;
        if let Some(p) = self.queue.front_mut() {
            if later >= 2 && !p.sacked && p.sent_at.is_some_and(|t| elapsed(now, t) >= guard) {
                p.sent_at = None;
            }
        }
    }

    fn push_event(&mut self, e: Event) {
        // Full: the event is dropped. Data frames check for room first and
        // so are retransmitted instead; a dropped datagram is allowed.
        let _ = self.events.push_back(e);
    }

    /// The current retransmission timeout, doubled per failure up to 16×.
    fn rto(&self) -> u32 {
        self.config.rto_ms.saturating_mul(1 << self.retries.min(4))
    }

    /// Runs the timers: link-loss detection and the retransmission timer.
    /// Call it every few milliseconds, and before [`Link::poll_transmit`].
    pub fn tick(&mut self, now: u32) {
        if self.up
            && self
                .last_rx
                .is_none_or(|t| elapsed(now, t) >= self.config.link_timeout_ms)
        {
            self.lose();
        }
        if !self.peer_synced {
            return;
        }
        let Some(sent) = self.queue.front().and_then(|p| p.sent_at) else {
            return;
        };
        if elapsed(now, sent) < self.rto() {
            return;
        }
        for p in self.queue.iter_mut().filter(|p| !p.sacked) {
            p.sent_at = None;
        }
        self.retries = self.retries.saturating_add(1);
        if self.retries > self.config.max_retries {
            self.lose();
        }
    }

    fn lose(&mut self) {
        if self.up {
            self.up = false;
            self.push_event(Event::LinkLost);
        }
    }

    /// Writes the next frame to send into `out` (at least
    /// [`super::MAX_FRAME_LEN`] bytes) and returns its length, or `None`
    /// when there is nothing to send now. Call it until it returns `None`.
    pub fn poll_transmit(&mut self, now: u32, out: &mut [u8]) -> Option<usize> {
        let mut header = Header {
            sender: self.local,
            session: self.session,
            peer_session: self.peer_session,
            seq: self.next_seq,
            ack: self.rx_next,
            // Filled in below, once there is a frame to send: most polls
            // have none, and the bits take a scan of the window.
            sack: 0,
        };
        let body = if !self.peer_synced
            && self
                .sync_sent_at
                .is_none_or(|t| elapsed(now, t) >= self.rto())
        {
            self.sync_sent_at = Some(now);
            header.seq = self.queue.front().map_or(self.next_seq, |p| p.seq);
            Body::Sync
        } else if let Some(p) = self
            .queue
            .iter_mut()
            .find(|p| p.sent_at.is_none() && !p.sacked)
            .filter(|_| self.peer_synced)
        {
            if p.sent_once {
                self.retransmissions = self.retransmissions.saturating_add(1);
            }
            p.sent_once = true;
            p.sent_at = Some(now);
            header.seq = p.seq;
            Body::Data(p.message.clone())
        } else if let Some(m) = self.datagram.take() {
            Body::Datagram(m)
        } else if self.ack_due
            || self
                .last_tx
                .is_none_or(|t| elapsed(now, t) >= self.config.heartbeat_ms)
        {
            Body::Ack
        } else {
            return None;
        };
        header.sack = self.sack();
        let n = Frame { header, body }.encode(out).ok()?;
        self.ack_due = false;
        self.last_tx = Some(now);
        self.tx_frames = self.tx_frames.saturating_add(1);
        self.tx_bytes = self
            .tx_bytes
            .saturating_add(u32::try_from(n).unwrap_or(u32::MAX));
        Some(n)
    }

    /// Whether [`Link::tick`], [`Link::poll_transmit`] and
    /// [`Link::poll_event`] would all do nothing at `now`, unless bytes
    /// arrive first. A host that serves many links at every event may skip
    /// the quiet ones: the simulator steps at every frame's arrival, and
    /// served all 32 link ends of 16 robots at each (with the codec, 45 %
    /// of a maze 256² run; docs/results/performance.md, stop 66). It asks
    /// what those calls ask, so skipping a quiet link changes nothing.
    pub fn is_quiet(&self, now: u32) -> bool {
        self.quiet_for(now) > 0
    }

    /// For how many ms from `now` the link stays quiet ([`Link::is_quiet`])
    /// unless bytes arrive or a message is sent: 0 if it is not quiet now.
    /// A host can then leave it alone until a timer runs out, without
    /// even asking it (u32::MAX: no timer runs).
    pub fn quiet_for(&self, now: u32) -> u32 {
        if self.ack_due || self.datagram.is_some() || !self.events.is_empty() {
            return 0;
        }
        // What is left of a timer started at `since` that runs out after
        // `after` ms; one never started has run out.
        let left = |since: Option<u32>, after: u32| {
            since.map_or(0, |t| after.saturating_sub(elapsed(now, t)))
        };
        let mut quiet = left(self.last_tx, self.config.heartbeat_ms);
        if self.up {
            quiet = quiet.min(left(self.last_rx, self.config.link_timeout_ms));
        }
        if !self.peer_synced {
            // Nothing is sent or resent unsynced but the Sync.
            return quiet.min(left(self.sync_sent_at, self.rto()));
        }
        if self.queue.iter().any(|p| p.sent_at.is_none() && !p.sacked) {
            return 0;
        }
        match self.queue.front().and_then(|p| p.sent_at) {
            Some(sent) => quiet.min(left(Some(sent), self.rto())),
            None => quiet,
        }
    }

    /// The next event, oldest first.
    pub fn poll_event(&mut self) -> Option<Event> {
        let e = self.events.pop_front();
        self.deliver();
        e
    }

    /// Whether the peer is heard and acknowledges.
    pub fn is_up(&self) -> bool {
        self.up
    }

    /// Whether [`Link::send`] would accept a message.
    pub fn can_send(&self) -> bool {
        !self.queue.is_full()
    }

    /// Reliable messages not yet acknowledged.
    pub fn unacked(&self) -> usize {
        self.queue.len()
    }

    /// The peer's address, once heard.
    pub fn peer(&self) -> Option<RobotId> {
        self.peer
    }

    /// This endpoint's session.
    pub fn session(&self) -> u8 {
        self.session
    }

    /// Frames sent again so far.
    pub fn retransmissions(&self) -> u32 {
        self.retransmissions
    }

    /// Frames sent so far (all kinds).
    pub fn tx_frames(&self) -> u32 {
        self.tx_frames
    }

    /// Bytes sent so far, delimiters included.
    pub fn tx_bytes(&self) -> u32 {
        self.tx_bytes
    }

    /// The stream decoder's counters (rejected frames and why).
    pub fn rx_stats(&self) -> Stats {
        self.decoder.stats()
    }
}
