//! The assignment solvers behind [`Candidates`]: the Hungarian algorithm
//! with potentials (min-sum, and min-max through a bottleneck threshold).

use super::{AssignmentObjective, Candidates, INF, MAX_CANDIDATES, is_left_out};
use crate::explore::MAX_ROBOTS;

/// Min-sum assignment of `k` rows (but the left-out ones) to `m ≥ k`
/// columns of `cost` (capped at `cap`: costlier pairs count as forbidden):
/// the Hungarian algorithm with potentials, O(k²·m). Returns the column
/// of each row, `None` where only a forbidden pair was left (and for
/// left-out rows), and each row's potential `u` (see [`Picks`](super::picks::Picks)).
pub(super) fn hungarian(
    c: &Candidates,
    cap: i64,
) -> ([Option<usize>; MAX_ROBOTS], [i64; MAX_ROBOTS]) {
    let cost = |i: usize, j: usize| -> i64 {
        if j >= c.m {
            // Dummy columns when there are fewer candidates than robots.
            return INF;
        }
        let x = c.at(i, j);
        if x > cap { INF } else { x }
    };
    let (p, u) =
        hungarian_by::<{ MAX_CANDIDATES + MAX_ROBOTS + 1 }>(c.k, c.m.max(c.k), c.left_out, cost);
    let mut out = [None; MAX_ROBOTS];
    for j in 1..=c.m.max(c.k) {
        let i = p.get(j).copied().unwrap_or(0);
        if i >= 1 && j <= c.m && cost(i - 1, j - 1) < INF {
            if let Some(x) = out.get_mut(i - 1) {
                *x = Some(j - 1);
            }
        }
    }
    let mut rows = [0i64; MAX_ROBOTS];
    for (r, x) in rows.iter_mut().zip(u.iter().skip(1)) {
        *r = *x;
    }
    (out, rows)
}

/// The Hungarian algorithm with potentials on `n` rows (but those in the
/// `skip` mask) and `m ≥ n` columns of `cost(row, column)` (0-based): the
/// row of each column, 1-based with 0 for none, at index column + 1, and
/// the rows' potentials at index row + 1, as in the textbook form. `C`
/// holds the columns and the virtual one (`m < C`); each row clears
/// arrays of that size, so a small problem takes a small `C`.
#[allow(clippy::type_complexity)]
pub(super) fn hungarian_by<const C: usize>(
    n: usize,
    m: usize,
    skip: u32,
    cost: impl Fn(usize, usize) -> i64,
) -> ([usize; C], [i64; MAX_ROBOTS + 1]) {
    // 1-based arrays as in the textbook form; column 0 is the virtual one.
    let mut u = [0i64; MAX_ROBOTS + 1];
    let mut v = [0i64; C];
    let mut p = [0usize; C];
    let mut way = [0usize; C];
    let get = |a: &[i64], i: usize| a.get(i).copied().unwrap_or(0);
    for i in 1..=n {
        if is_left_out(skip, i - 1) {
            continue;
        }
        if let Some(x) = p.get_mut(0) {
            *x = i;
        }
        let mut j0 = 0usize;
        let mut minv = [INF * 4; C];
        let mut used = [false; C];
        for _ in 0..=m {
            if let Some(x) = used.get_mut(j0) {
                *x = true;
            }
            let i0 = p.get(j0).copied().unwrap_or(0);
            let mut delta = INF * 4;
            let mut j1 = 0usize;
            for j in 1..=m {
                if used.get(j).copied().unwrap_or(true) {
                    continue;
                }
                let cur = cost(i0.wrapping_sub(1), j - 1) - get(&u, i0) - get(&v, j);
                if cur < minv.get(j).copied().unwrap_or(0) {
                    if let Some(x) = minv.get_mut(j) {
                        *x = cur;
                    }
                    if let Some(x) = way.get_mut(j) {
                        *x = j0;
                    }
                }
                let mj = minv.get(j).copied().unwrap_or(0);
                if mj < delta {
                    delta = mj;
                    j1 = j;
                }
            }
            for j in 0..=m {
                let pj = p.get(j).copied().unwrap_or(0);
                if used.get(j).copied().unwrap_or(false) {
                    if let Some(x) = u.get_mut(pj) {
                        *x += delta;
                    }
                    if let Some(x) = v.get_mut(j) {
                        *x -= delta;
                    }
                } else if let Some(x) = minv.get_mut(j) {
                    *x -= delta;
                }
            }
            j0 = j1;
            if p.get(j0).copied().unwrap_or(0) == 0 {
                break;
            }
        }
        loop {
            let j1 = way.get(j0).copied().unwrap_or(0);
            let pj1 = p.get(j1).copied().unwrap_or(0);
            if let Some(x) = p.get_mut(j0) {
                *x = pj1;
            }
            j0 = j1;
            if j0 == 0 {
                break;
            }
        }
    }
    (p, u)
}

/// The smallest threshold under which every row can still be matched, for
/// the bottleneck (min-max) objective.
fn bottleneck_threshold(c: &Candidates) -> i64 {
    let mut vals = [INF; MAX_ROBOTS * MAX_CANDIDATES];
    let mut n = 0usize;
    for j in 0..c.k {
        for col in 0..c.m {
            let x = c.at(j, col);
            if x < INF {
                if let Some(s) = vals.get_mut(n) {
                    *s = x;
                    n += 1;
                }
            }
        }
    }
    let Some(vals) = vals.get_mut(..n) else {
        return INF;
    };
    vals.sort_unstable();
    let full = hungarian(c, INF)
        .0
        .iter()
        .take(c.k)
        .filter(|x| x.is_some())
        .count();
    let (mut lo, mut hi) = (0usize, n);
    while lo < hi {
        let mid = (lo + hi) / 2;
        let cap = vals.get(mid).copied().unwrap_or(INF);
        let got = hungarian(c, cap)
            .0
            .iter()
            .take(c.k)
            .filter(|x| x.is_some())
            .count();
        if got >= full { hi = mid } else { lo = mid + 1 }
    }
    vals.get(lo).copied().unwrap_or(INF)
}

/// The column of every row under `objective`.
pub(crate) fn hungarian_cols(
    c: &Candidates,
    objective: AssignmentObjective,
) -> [Option<usize>; MAX_ROBOTS] {
    let cap = match objective {
        AssignmentObjective::MinSum => INF - 1,
        AssignmentObjective::MinMax => bottleneck_threshold(c),
    };
    hungarian(c, cap).0
}
