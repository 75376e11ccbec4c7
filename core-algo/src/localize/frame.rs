//! Frames and how the team joins them.
//!
//! Before localization every robot lives in its own frame: its start node
//! is the origin and its start heading is north. A contact between two
//! robots tells how one frame lies in the other ([`Frame::from_contact`]);
//! [`TeamFrames`] joins frames contact by contact (a union-find over at
//! most [`MAX_ROBOTS`] robots) until one frame, the lowest id's, holds
//! every robot.

use crate::explore::MAX_ROBOTS;
use crate::geometry::{Heading, Pos};
use crate::protocol::Pose;
use crate::team::RobotId;

/// A rigid motion of the lattice: turn clockwise by `quarter_turns` × 90°
/// about the origin, then shift by (`dx`, `dy`). Maps poses of one robot's
/// frame into another's; lattice frames differ by nothing else.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Frame {
    /// Clockwise quarter turns, 0..=3.
    pub quarter_turns: u8,
    /// Shift along x after the turn.
    pub dx: i16,
    /// Shift along y after the turn.
    pub dy: i16,
}

impl Frame {
    /// The frame that changes nothing.
    pub const IDENTITY: Frame = Frame {
        quarter_turns: 0,
        dx: 0,
        dy: 0,
    };

    /// Turns `(x, y)` clockwise by the frame's quarter turns (y points
    /// north, so one quarter turn takes north (0, 1) to east (1, 0)).
    fn turn(self, x: i16, y: i16) -> (i16, i16) {
        match self.quarter_turns & 3 {
            0 => (x, y),
            1 => (y, x.wrapping_neg()),
            2 => (x.wrapping_neg(), y.wrapping_neg()),
            _ => (y.wrapping_neg(), x),
        }
    }

    /// Where node `p` lies in the target frame.
    pub fn pos(self, p: Pos) -> Pos {
        let (x, y) = self.turn(p.x, p.y);
        Pos::new(x.wrapping_add(self.dx), y.wrapping_add(self.dy))
    }

    /// Which way heading `h` points in the target frame.
    pub fn heading(self, h: Heading) -> Heading {
        Heading::from_index(h.index() + self.quarter_turns)
    }

    /// A pose in the target frame.
    pub fn pose(self, p: Pose) -> Pose {
        Pose {
            pos: self.pos(p.pos),
            heading: self.heading(p.heading),
        }
    }

    /// `self` after `first`: maps like `first`, then like `self`.
    pub fn after(self, first: Frame) -> Frame {
        let (x, y) = self.turn(first.dx, first.dy);
        Frame {
            quarter_turns: (self.quarter_turns + first.quarter_turns) & 3,
            dx: x.wrapping_add(self.dx),
            dy: y.wrapping_add(self.dy),
        }
    }

    /// The frame that undoes `self`.
    pub fn inverse(self) -> Frame {
        let back = Frame {
            quarter_turns: (4 - (self.quarter_turns & 3)) & 3,
            dx: 0,
            dy: 0,
        };
        let (x, y) = back.turn(self.dx, self.dy);
        Frame {
            dx: x.wrapping_neg(),
            dy: y.wrapping_neg(),
            ..back
        }
    }

    /// The frame that takes pose `theirs` (the active robot's pose in its
    /// own frame at a contact) to `seen` (the same pose as the passive
    /// partner places it in its own frame).
    pub fn from_contact(theirs: Pose, seen: Pose) -> Frame {
        let turn = Frame {
            quarter_turns: (seen.heading.index() + 4 - theirs.heading.index()) & 3,
            dx: 0,
            dy: 0,
        };
        let turned = turn.pos(theirs.pos);
        Frame {
            dx: seen.pos.x.wrapping_sub(turned.x),
            dy: seen.pos.y.wrapping_sub(turned.y),
            ..turn
        }
    }
}

/// One contact: robot `active` stood at `theirs` in its own frame and
/// touched robot `passive`, which places that pose at `seen` in its own.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Contact {
    /// The robot that drove.
    pub active: RobotId,
    /// Its pose at the contact, its own frame.
    pub theirs: Pose,
    /// The robot that stood.
    pub passive: RobotId,
    /// The active robot's pose, the passive robot's frame.
    pub seen: Pose,
}

/// Which robots share a frame, and how each robot's own frame maps into
/// its group's frame (the frame of the group's lowest id).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct TeamFrames {
    team: u8,
    root: [u8; MAX_ROBOTS],
    to_root: [Frame; MAX_ROBOTS],
}

impl TeamFrames {
    /// `team` robots (at most [`MAX_ROBOTS`]), each alone in its frame.
    pub fn new(team: u8) -> Self {
        let team = team.clamp(1, MAX_ROBOTS as u8);
        TeamFrames {
            team,
            root: core::array::from_fn(|i| i as u8),
            to_root: [Frame::IDENTITY; MAX_ROBOTS],
        }
    }

    /// Team size.
    pub fn team(&self) -> u8 {
        self.team
    }

    /// The lowest id of `id`'s group: whose frame the group uses.
    pub fn root(&self, id: RobotId) -> RobotId {
        RobotId(self.root.get(id.index()).copied().unwrap_or(id.0))
    }

    /// How `id`'s own frame maps into its group's frame.
    pub fn to_root(&self, id: RobotId) -> Frame {
        self.to_root
            .get(id.index())
            .copied()
            .unwrap_or(Frame::IDENTITY)
    }

    /// Number of groups: 1 once the team shares one frame.
    pub fn groups(&self) -> u8 {
        (0..self.team)
            .filter(|&i| self.root(RobotId(i)).0 == i)
            .count() as u8
    }

    /// Whether every robot is in robot 0's frame.
    pub fn joined(&self) -> bool {
        self.groups() == 1
    }

    /// Joins the groups of a contact's two robots; returns whether they
    /// were apart (the contact taught something new).
    pub fn join(&mut self, c: Contact) -> bool {
        let (a, b) = (c.active, c.passive);
        if a.0 >= self.team || b.0 >= self.team {
            return false;
        }
        let (ra, rb) = (self.root(a), self.root(b));
        if ra == rb {
            return false;
        }
        // a's own frame → b's own frame.
        let a_to_b = Frame::from_contact(c.theirs, c.seen);
        // rb's frame → ra's frame: back into b's frame, over to a's, up to ra.
        let rb_to_ra = self
            .to_root(a)
            .after(a_to_b.inverse())
            .after(self.to_root(b).inverse());
        let (keep, gone, gone_to_keep) = if ra.0 < rb.0 {
            (ra, rb, rb_to_ra)
        } else {
            (rb, ra, rb_to_ra.inverse())
        };
        for i in 0..usize::from(self.team) {
            if self.root.get(i).copied() == Some(gone.0) {
                if let Some(r) = self.root.get_mut(i) {
                    *r = keep.0;
                }
                if let Some(f) = self.to_root.get_mut(i) {
                    *f = gone_to_keep.after(*f);
                }
            }
        }
        true
    }
}
