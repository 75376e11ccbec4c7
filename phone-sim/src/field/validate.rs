//! The one validator every loader and generator shares.

use super::StartPose;
use core_algo::geometry::{Arms, Heading, Pos};
use std::collections::{BTreeMap, HashSet};
use std::fmt;

/// One inconsistency in a field.
#[derive(Clone, PartialEq, Eq, Debug)]
pub enum Problem {
    /// The field has no node at all.
    Empty,
    /// An arm leads where there is no node.
    ArmIntoNothing {
        /// The node with the arm.
        pos: Pos,
        /// The arm.
        heading: Heading,
    },
    /// An arm leads to a node without the matching arm back.
    ArmNotReturned {
        /// The node with the arm.
        pos: Pos,
        /// The arm.
        heading: Heading,
    },
    /// A start pose is not on a node.
    StartOffField {
        /// Index of the start (robot id).
        index: usize,
        /// Its position.
        pos: Pos,
    },
    /// Two robots would start on the same node.
    StartShared {
        /// Index of the second start.
        index: usize,
        /// The shared node.
        pos: Pos,
    },
    /// Some nodes cannot be reached from the others.
    Disconnected {
        /// Number of connected parts.
        parts: usize,
        /// A node outside the part of the first node.
        unreachable: Pos,
    },
}

impl Problem {
    /// The node the problem is about, so that loaders can point at its line.
    pub fn pos(&self) -> Option<Pos> {
        match self {
            Problem::Empty => None,
            Problem::ArmIntoNothing { pos, .. }
            | Problem::ArmNotReturned { pos, .. }
            | Problem::Disconnected {
                unreachable: pos, ..
            } => Some(*pos),
            Problem::StartOffField { pos, .. } | Problem::StartShared { pos, .. } => Some(*pos),
        }
    }

    /// Whether the problem concerns a start pose (its line is the start's).
    pub fn start_index(&self) -> Option<usize> {
        match self {
            Problem::StartOffField { index, .. } | Problem::StartShared { index, .. } => {
                Some(*index)
            }
            _ => None,
        }
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Problem::Empty => write!(f, "expected at least one node, found none"),
            Problem::ArmIntoNothing { pos, heading } => write!(
                f,
                "node {pos} has an arm {heading}, but there is no node at {}",
                pos.step(*heading)
                    .map_or("the edge of the coordinate range".into(), |q| q.to_string())
            ),
            Problem::ArmNotReturned { pos, heading } => write!(
                f,
                "node {pos} has an arm {heading}, but the node there has no arm {} back",
                heading.opposite()
            ),
            Problem::StartOffField { index, pos } => {
                write!(f, "start {index} at {pos} is not on a node")
            }
            Problem::StartShared { index, pos } => {
                write!(
                    f,
                    "start {index} at {pos} shares its node with an earlier start"
                )
            }
            Problem::Disconnected { parts, unreachable } => write!(
                f,
                "expected one connected field, found {parts} parts: node {unreachable} cannot be reached from the first node"
            ),
        }
    }
}

/// Every problem found in a field, in a deterministic order (arms by node,
/// then starts, then connectivity).
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct ValidationError {
    /// The problems; never empty.
    pub problems: Vec<Problem>,
}

impl fmt::Display for ValidationError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(first) = self.problems.first() {
            write!(f, "{first}")?;
        }
        if self.problems.len() > 1 {
            write!(f, " (and {} more problems)", self.problems.len() - 1)?;
        }
        Ok(())
    }
}

impl std::error::Error for ValidationError {}

/// Checks a node set and its starts; see [`Problem`] for what is checked.
pub fn check(nodes: &BTreeMap<Pos, Arms>, starts: &[StartPose]) -> Result<(), ValidationError> {
    let mut problems = Vec::new();
    if nodes.is_empty() {
        problems.push(Problem::Empty);
    }
    for (&pos, &arms) in nodes {
        for heading in arms.iter() {
            match pos.step(heading).and_then(|q| nodes.get(&q)) {
                None => problems.push(Problem::ArmIntoNothing { pos, heading }),
                Some(back) if !back.has(heading.opposite()) => {
                    problems.push(Problem::ArmNotReturned { pos, heading })
                }
                Some(_) => {}
            }
        }
    }
    let mut taken = HashSet::new();
    for (index, s) in starts.iter().enumerate() {
        if !nodes.contains_key(&s.pos) {
            problems.push(Problem::StartOffField { index, pos: s.pos });
        } else if !taken.insert(s.pos) {
            problems.push(Problem::StartShared { index, pos: s.pos });
        }
    }
    if let Some(problem) = connectivity(nodes) {
        problems.push(problem);
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(ValidationError { problems })
    }
}

/// Connected parts over edges present in both directions' arm sets (an arm
/// without its return is reported separately, so one arm is enough here).
fn connectivity(nodes: &BTreeMap<Pos, Arms>) -> Option<Problem> {
    let mut seen: HashSet<Pos> = HashSet::with_capacity(nodes.len());
    let mut parts = 0;
    let mut unreachable = None;
    let mut stack = Vec::new();
    for &start in nodes.keys() {
        if seen.contains(&start) {
            continue;
        }
        parts += 1;
        if parts == 2 {
            unreachable = Some(start);
        }
        seen.insert(start);
        stack.push(start);
        while let Some(p) = stack.pop() {
            for h in Heading::ALL {
                let Some(q) = p.step(h) else { continue };
                let Some(qa) = nodes.get(&q) else { continue };
                let pa = nodes.get(&p).copied().unwrap_or_default();
                if (pa.has(h) || qa.has(h.opposite())) && seen.insert(q) {
                    stack.push(q);
                }
            }
        }
    }
    unreachable.map(|unreachable| Problem::Disconnected { parts, unreachable })
}

/// Keeps only the largest connected part (ties: the part of the smallest
/// node); returns how many nodes were dropped. Used by importers of formats
/// that can describe several parts, such as Moving AI grids.
pub fn keep_largest_part(nodes: &mut BTreeMap<Pos, Arms>) -> usize {
    let mut best: Vec<Pos> = Vec::new();
    let mut seen: HashSet<Pos> = HashSet::with_capacity(nodes.len());
    for &start in nodes.keys() {
        if seen.contains(&start) {
            continue;
        }
        seen.insert(start);
        let mut part = vec![start];
        let mut k = 0;
        while let Some(&p) = part.get(k) {
            k += 1;
            let pa = nodes.get(&p).copied().unwrap_or_default();
            for h in pa.iter() {
                if let Some(q) = p.step(h)
                    && nodes.contains_key(&q)
                    && seen.insert(q)
                {
                    part.push(q);
                }
            }
        }
        if part.len() > best.len() {
            best = part;
        }
    }
    let keep: HashSet<Pos> = best.into_iter().collect();
    let before = nodes.len();
    nodes.retain(|p, _| keep.contains(p));
    before - nodes.len()
}
