//! Tempo's knobs and the size rules that switch them on.

use super::FarRule;

/// Tempo's knobs; [`Default`] holds the benchmarked values.
#[derive(Clone, Copy, Debug)]
pub struct TempoConfig {
    /// Extra cost, in edges, of a frontier node with three visited
    /// neighbours.
    pub deduce_penalty_edges: u32,
    /// In the endgame, minimise the largest travel plus way home.
    pub endgame_return: bool,
    /// Keep a robot's share while the map is unchanged instead of
    /// re-assigning the team at every node (see `Commitment`).
    pub keep_share: bool,
    /// A robot without a share goes home.
    pub idle_home: bool,
    /// A robot without a share waits where it is (it decides again when the
    /// map grows); takes precedence over `idle_home`.
    pub idle_stay: bool,
    /// With `idle_stay`: a robot without a share still trails to its
    /// nearest frontier node when that is at most this many edges of time
    /// away (0: never)...
    pub trail_edges: u32,
    /// ...while the team has at most this many robots: beyond, idle robots
    /// wait (see the module docs).
    pub trail_team: usize,
    /// A team with at least this many nodes of the map window per robot
    /// trails any distance, not only `trail_edges` (0: never): in a sparse
    /// team trailers rarely jam, and in a large maze the work is often far
    /// down a corridor.
    pub trail_far_nodes_per_robot: u32,
    /// Teams of at most this many robots collect every robot's k cheapest
    /// frontier nodes; larger ones start from 4 each and prove the
    /// assignment optimal, growing picks where the proof fails (see
    /// `assign::Picks`). Both find a min-sum optimum, but they break ties
    /// differently: on small fields, where collecting costs little, the
    /// eager ties measured 0.6 % shorter makespans.
    pub eager_team: usize,
    /// Candidates closer than this Manhattan distance to a candidate taken
    /// already are skipped, so that robots split into regions.
    pub spread: u32,
    /// Assign on squared travel times (in edges): a convex cost that
    /// balances the robots' shares, between min-sum and min-max.
    pub squared: bool,
    /// Percent of a candidate's distance from the robot's home (Manhattan,
    /// in edges) taken off its cost: far frontier nodes first, so that what
    /// is left at the end lies near home, on the way back.
    pub home_pull_pct: u32,
    /// With `keep_share`: map changes a kept share survives before the
    /// team is re-assigned (0: only an unchanged map keeps it, which loses
    /// no optimal assignment; see `Commitment`).
    pub share_slack: u32,
    /// With `keep_share`: a robot on a corridor node (two known arms) keeps
    /// its share whatever changed in the map, as long as the share is still
    /// a frontier node, and decides afresh at the next junction. In a
    /// corridor it can only go on or turn back, and a fresh decision chose
    /// another share in one of 13 corridor decisions of a 16-robot 64²
    /// maze; a full decision at every corridor node was a quarter of such
    /// a run's decisions, each growing fields over most of the maze. Not
    /// exact, unlike an unchanged map:
    /// measured neutral on small and 64² fields and 4–5 % shorter on large
    /// mazes (docs/results/performance.md, stop 26).
    pub corridor_keeps_share: bool,
    /// With `keep_share`: in teams of more than this many robots, on a
    /// maze-like map (at least half the visited nodes with two arms, as
    /// for jumping searches), a robot that reaches its share and finds a
    /// corridor node there, leading on to a frontier node no team mate has
    /// announced, takes that node as its next share without re-assigning
    /// the team (`Commitment::onward`). Not exact, like
    /// `corridor_keeps_share`: on mazes every makespan measured was the
    /// same; on rooms fields, where few nodes are corridors, single runs
    /// went −2.9 % to +2.4 % and not faster (docs/results/performance.md,
    /// stop 52).
    pub corridor_extends_team: usize,
    /// Teams of more than this many robots break ties between equally
    /// cheap assignments by a tie-break that every robot computes alike
    /// (see the module docs). Small
    /// teams keep the Hungarian's own order (the deciding robot's nearest
    /// frontier node first), which measured 1.5 % shorter on 12² and 16²
    /// fields; teams of 10 and 16 on 40² fields were 3.6 % shorter with
    /// the tie-break (docs/results/performance.md, stop 28). The team is
    /// the one the deciding robot knows of.
    pub tie_break_team: usize,
    /// Extra cost, in edges, of a frontier node at a team mate's announced
    /// target, falling linearly to 0 beyond `crowd_radius` (Manhattan): a
    /// soft push apart, like Burgard's utility discount, on top of the
    /// min-sum assignment, which keeps robots off one node but not off
    /// one room. In teams of at most `crowd_team` only.
    pub crowd_penalty_edges: u32,
    /// See `crowd_penalty_edges`.
    pub crowd_radius: u32,
    /// See `crowd_penalty_edges`: larger teams measured 1.5 % slower with
    /// it (docs/results/exploration.md, stop 34).
    pub crowd_team: usize,
    /// With `keep_share`: a robot at least this many edges (Manhattan)
    /// from its share keeps it whatever changed in the map, while no team
    /// mate has announced it (0: never), and team mates leave it out of
    /// their assignments (see the module docs). Not exact, like
    /// `corridor_keeps_share`; without `far_nearer`, 12 lost 3 % on 40²
    /// fields with 10 and 16 robots, 24 lost nothing.
    pub far_keeps_share: u32,
    /// `far_keeps_share` holds in teams of more than this many robots.
    pub far_keeps_share_team: usize,
    /// With `far_keeps_share`: n > 0 ends a far share when another robot
    /// stands within 1/n of the distance of it (0: never). Without it,
    /// rooms and mazes ran far faster (rooms 256² in about 2 minutes, not
    /// over 9), but open and random 256² fields took 4–5 % longer: a far
    /// robot's share was left to it even with a team mate next to it.
    pub far_nearer: u32,
    /// With `far_nearer`: in a team with at least this many nodes of the
    /// map window per robot (0: never), a robot near a far share does not
    /// end it while it heads for an announced target no farther from it
    /// than the share. On large fields a team mate in the next room, near
    /// by Manhattan distance but busy there, ended far shares again and
    /// again, and every robot then searched the far robot's field. At 256²
    /// with 16 robots (4 160 nodes each) rooms ran 2.3 to 6 times faster,
    /// a maze 2.6 times and 30 % shorter, random up to 2.7 times, with
    /// makespans even over the other seven runs (geometric mean 0.987,
    /// single runs −7 % to +9 %); but 128² mazes took 4–6 % longer and
    /// 40² fields 0.8 %, hence the limit (docs/results/performance.md,
    /// stop 39).
    pub far_busy_nodes_per_robot: u32,
    /// In teams of more than `cluster_team`, robots chained by steps of at
    /// most this Manhattan distance (in edges) between where they stand or
    /// head form a cluster, and a deciding robot assigns only its own
    /// cluster (0: the whole team). Team mates outside it are left out,
    /// their announced targets with them. Off: see the module docs.
    pub cluster_radius: u32,
    /// See `cluster_radius`.
    pub cluster_team: usize,
}

impl TempoConfig {
    /// Whether a team of `robots` on a map window of `area` nodes trails
    /// any distance (see `trail_far_nodes_per_robot`).
    pub(super) fn trails_far(&self, area: usize, robots: usize) -> bool {
        has_per_robot(area, robots, self.trail_far_nodes_per_robot)
    }

    /// When a team of `robots` on a map window of `area` nodes keeps far
    /// shares (see `far_keeps_share`, `far_nearer` and
    /// `far_busy_nodes_per_robot`).
    pub(super) fn far_rule(&self, area: usize, robots: usize) -> FarRule {
        if !self.keep_share || robots <= self.far_keeps_share_team {
            return FarRule::default();
        }
        FarRule {
            edges: self.far_keeps_share,
            nearer: self.far_nearer,
            nearer_busy: has_per_robot(area, robots, self.far_busy_nodes_per_robot),
        }
    }
}

/// Whether a team of `robots` on a map window of `area` nodes has at least
/// `nodes` of it per robot (0: never): the size rule of the knobs that pay
/// only on sparse teams or large fields.
fn has_per_robot(area: usize, robots: usize, nodes: u32) -> bool {
    nodes > 0 && area / robots.max(1) >= nodes as usize
}

impl Default for TempoConfig {
    fn default() -> Self {
        TempoConfig {
            deduce_penalty_edges: 0,
            endgame_return: false,
            keep_share: true,
            idle_home: true,
            idle_stay: true,
            trail_edges: 8,
            trail_team: 6,
            trail_far_nodes_per_robot: 48,
            eager_team: 6,
            spread: 0,
            squared: false,
            home_pull_pct: 25,
            share_slack: 0,
            corridor_keeps_share: true,
            corridor_extends_team: 6,
            tie_break_team: 6,
            crowd_penalty_edges: 2,
            crowd_radius: 4,
            crowd_team: 6,
            far_keeps_share: 24,
            far_keeps_share_team: 6,
            far_nearer: 2,
            far_busy_nodes_per_robot: 4096,
            cluster_radius: 0,
            cluster_team: 6,
        }
    }
}
