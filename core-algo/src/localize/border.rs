//! Global localization's phase 1 (seed §4.3): a robot finds the outer
//! border by climbing north and tracing faces, climbing again over inner
//! faces; `docs/localization.md` argues why it ends.

use super::*;

impl Localizer {
    /// The arms of this node not known to lead to a robot.
    fn open(&self) -> Arms {
        let mut open = self.here;
        for h in Heading::ALL {
            if self.pos.step(h).is_some_and(|q| self.blocked.contains(&q)) {
                open = open.without(h);
            }
        }
        open
    }

    pub(super) fn block(&mut self, node: Option<Pos>) {
        if let Some(q) = node
            && !self.blocked.contains(&q)
        {
            // Full only with more contacts than robots, which a static
            // team cannot produce; the walk then just tries again.
            let _ = self.blocked.push(q);
        }
    }

    /// Global: drive north while there is a line; then trace.
    pub(super) fn climb(&mut self, out: &mut Steps) {
        self.task = Task::Climb;
        if self.open().has(Heading::North) {
            self.go(Heading::North, out);
        } else {
            self.begin_trace(out);
        }
    }

    /// Global: trace the face north of this node, as if arriving heading
    /// east (north then lies on the left).
    pub(super) fn begin_trace(&mut self, out: &mut Steps) {
        self.arrival = Heading::East;
        match left_first(Heading::East, self.open()) {
            Some((d, _)) => {
                self.task = Task::Trace(Trace::new(self.pos, d));
                self.go(d, out);
            }
            // A node without (free) arms is all of its component.
            None => self.found(None, out),
        }
    }

    /// Global: the trace's decision on the node it stands on.
    pub(super) fn trace_step(&mut self, mut t: Trace, out: &mut Steps) {
        let Some((d, turn)) = left_first(self.arrival, self.open()) else {
            // Robots stand on every neighbour: this node is all of its
            // component, and its border.
            self.found(None, out);
            return;
        };
        if t.closes(self.pos, d) {
            let sum = t.sum.saturating_add(i16::from(turn));
            if sum < 0 {
                // −4: the outer border. Stay here, ready to circle.
                self.found(Some(d), out);
            } else if self.pos == t.top {
                self.climb(out);
            } else {
                // +4: an inner face; round it to its topmost node.
                self.task = Task::ToTop { top: t.top };
                self.go(d, out);
            }
            return;
        }
        t.sum = t.sum.saturating_add(i16::from(turn));
        t.pending = turn;
        self.task = Task::Trace(t);
        self.go(d, out);
    }

    /// Global: one more node along the face.
    pub(super) fn walk_on(&mut self, out: &mut Steps) {
        match left_first(self.arrival, self.open()) {
            Some((d, _)) => self.go(d, out),
            None => self.fail(Failure::Refused),
        }
    }

    pub(super) fn found(&mut self, first: Option<Heading>, out: &mut Steps) {
        self.walk_next = first;
        self.blocked.clear();
        self.pass(out);
    }
}
