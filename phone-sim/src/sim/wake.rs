//! When each robot's parts next need the simulator.
//!
//! A step serves a robot's firmware only at a tick, a report of its body,
//! a frame arriving or its link end's timer running out, and its proxy
//! only at a frame or a timer. Most steps are one frame arriving at one
//! robot; serving every robot's two link ends at each, reading each from
//! memory, was a sixth of a maze 128² run with 16 robots
//! (docs/results/performance.md, stop 66). A link end's timers come from
//! `Link::quiet_for`, read as it was last served; nothing else touches it
//! meanwhile, so each is served at the steps it was before.
//!
//! Times are kept as flat arrays, `u32::MAX` for never (the clock stops
//! before it), so that a step's scans are a few compares over 64 bytes.

/// When each robot's firmware, proxy and channels are next due.
#[derive(Clone, Debug)]
pub(super) struct Wakes {
    /// The firmware's link end is quiet before then.
    firmware: Vec<u32>,
    /// The proxy's link end is quiet before then.
    proxy: Vec<u32>,
    /// The next frame's arrival at the phone.
    up: Vec<u32>,
    /// The next frame's arrival at the robot.
    down: Vec<u32>,
}

const NEVER: u32 = u32::MAX;

impl Wakes {
    /// A team of `robots`, each due at once.
    pub(super) fn new(robots: usize) -> Self {
        Wakes {
            firmware: vec![0; robots],
            proxy: vec![0; robots],
            up: vec![NEVER; robots],
            down: vec![NEVER; robots],
        }
    }

    /// The next frame to arrive anywhere.
    pub(super) fn next_arrival(&self) -> Option<u32> {
        let up = self.up.iter().copied().min().unwrap_or(NEVER);
        let down = self.down.iter().copied().min().unwrap_or(NEVER);
        Some(up.min(down)).filter(|&t| t != NEVER)
    }

    /// Whether robot `i`'s firmware has a frame or a timer due at `now`
    /// (ticks and reports aside, which the step knows).
    pub(super) fn firmware_due(&self, i: usize, now: u32) -> bool {
        let at = |v: &[u32]| v.get(i).is_none_or(|&t| t <= now);
        at(&self.firmware) || at(&self.down)
    }

    /// Whether robot `i`'s proxy has a frame or a timer due at `now`.
    pub(super) fn proxy_due(&self, i: usize, now: u32) -> bool {
        let at = |v: &[u32]| v.get(i).is_none_or(|&t| t <= now);
        at(&self.proxy) || at(&self.up)
    }

    /// Robot `i`'s firmware was served at `now`: its link end is quiet
    /// for `quiet` ms, and its channels deliver next at `up` and `down`.
    pub(super) fn firmware_served(&mut self, i: usize, now: u32, quiet: u32, arrivals: Arrivals) {
        set(&mut self.firmware, i, now.saturating_add(quiet));
        self.arrivals(i, arrivals);
    }

    /// Robot `i`'s proxy was served, or sent to, at `now`.
    pub(super) fn proxy_served(&mut self, i: usize, now: u32, quiet: u32, arrivals: Arrivals) {
        set(&mut self.proxy, i, now.saturating_add(quiet));
        self.arrivals(i, arrivals);
    }

    /// A message was sent to robot `i`'s proxy from outside a step.
    pub(super) fn proxy_now(&mut self, i: usize) {
        set(&mut self.proxy, i, 0);
    }

    fn arrivals(&mut self, i: usize, (up, down): Arrivals) {
        set(&mut self.up, i, up.unwrap_or(NEVER));
        set(&mut self.down, i, down.unwrap_or(NEVER));
    }
}

/// The next arrivals on a robot's (up, down) channels.
pub(super) type Arrivals = (Option<u32>, Option<u32>);

fn set(v: &mut [u32], i: usize, t: u32) {
    if let Some(slot) = v.get_mut(i) {
        *slot = t;
    }
}
