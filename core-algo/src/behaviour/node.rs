//! Layer 4: node analysis while driving.
//!
//! Wraps the [`NodeDetector`]: while it sees a crossing, this layer drives
//! straight and so switches line following off; when the axle is over the
//! node it stops the robot and reports the node's relative arms.

use super::{Act, Context, Event, Layer, Mode};
use crate::control::Wheels;
use crate::control::node_detect::{NodeConfig, NodeDetector, NodeStep};

/// The node-analysis layer.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct NodeLayer {
    detector: NodeDetector,
    epoch: u32,
}

impl NodeLayer {
    /// A layer with the given node geometry.
    pub const fn new(config: NodeConfig) -> NodeLayer {
        NodeLayer {
            detector: NodeDetector::new(config),
            epoch: u32::MAX,
        }
    }
}

impl Layer for NodeLayer {
    fn act(&mut self, ctx: &mut Context<'_>) -> Option<Act> {
        if ctx.state.mode != Mode::Moving {
            return None;
        }
        let floor = ctx.floor?;
        if self.epoch != ctx.state.epoch {
            self.detector.reset();
            self.epoch = ctx.state.epoch;
        }
        let steps = ctx.sensors.steps;
        match self
            .detector
            .update(floor, steps.travelled_since(ctx.state.departed))
        {
            NodeStep::Follow => None,
            NodeStep::Cross => Some(Act::drive(Wheels::straight(ctx.state.speed))),
            NodeStep::Arrived(arms) => {
                ctx.state.enter(Mode::OnNode, steps);
                ctx.state.departed = steps;
                Some(Act::stop_with(Event::NodeHit { arms }))
            }
        }
    }
}
