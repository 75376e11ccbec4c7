//! Studies behind docs/results/control.md, "Ziegler–Nichols auto-tuning" (all
//! ignored; run with `-- --ignored --nocapture`): a P-only gain ramp, the relay
//! experiment under other relay settings, the load-disturbance sweep at chosen
//! disturbance sizes (env D, DEG, SEEDS, BASE) and a multi-seed task sweep.

use core_algo::behaviour::{Command, Config};
use core_algo::control::Wheels;
use core_algo::control::line_follow::line_error;
use core_algo::control::pid::{Fix, Gains, Relay, RelayTuner};
use core_algo::geometry::{Heading, Pos};
use phone_sim::sensor_world::field::LineField;
use phone_sim::sensor_world::scenario::*;
use phone_sim::sensor_world::{SimConfig, World};

fn config() -> Config {
    let mut c = Config::EPUCK;
    c.node.node_spacing_steps = 0;
    c
}

fn long_line(n: i16) -> LineField {
    let mut field = LineField::new(1, n, 100.0, 12.0);
    for y in 0..n - 1 {
        field.connect(Pos::new(0, y), Heading::North);
    }
    field
}

/// Runs `gains` on a straight line; returns sensor offset series (mm) and errors.
fn run(
    gains: Gains,
    seed: u64,
    deg: f64,
    lateral: f64,
    steps: usize,
    speed: i16,
    sim: SimConfig,
) -> (Vec<f64>, Vec<i32>) {
    let mut w = World::new(long_line(40), sim, seed);
    let mut cfg = config();
    cfg.gains = gains;
    let i = calibrated_robot(&mut w, cfg, Pos::new(0, 0), Heading::North);
    w.order(i, Command::SetSpeed(speed)).unwrap();
    let p = &mut w.robots[i].body.pose;
    p.theta += deg.to_radians();
    p.x += lateral;
    w.order(i, Command::Move).unwrap();
    let cal = w.robots[i].robot.calibration().unwrap();
    let mut ys = Vec::new();
    let mut es = Vec::new();
    for _ in 0..steps {
        let ev = w.step();
        let pose = w.robots[i].body.pose;
        let (sx, _) = pose.point(w.geometry.floor_forward_mm, 0.0);
        ys.push(sx);
        es.push(line_error(cal.apply(w.robots[i].sensors.floor)));
        if ev.iter().any(|e| e.robot == i) {
            break;
        }
    }
    (ys, es)
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

/// Mean period from upward zero crossings of (v - mean).
fn period(v: &[f64]) -> f64 {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    let mut ups = Vec::new();
    for k in 1..v.len() {
        if v[k - 1] - m < 0.0 && v[k] - m >= 0.0 {
            ups.push(k);
        }
    }
    if ups.len() < 2 {
        return f64::NAN;
    }
    (ups[ups.len() - 1] - ups[0]) as f64 / (ups.len() - 1) as f64
}

#[test]
#[ignore]
fn gain_ramp() {
    let sim: SimConfig = std::env::var("NOISELESS")
        .map(|_| SimConfig {
            floor_noise: 0.0,
            slip: 0.0,
            ..SimConfig::default()
        })
        .unwrap_or_default();
    for k10 in [
        10, 30, 100, 200, 300, 400, 500, 600, 800, 1000, 1300, 1600, 2000,
    ] {
        let k = Fix::from_num(k10) / 10;
        let g = Gains {
            kp: k,
            ki: Fix::ZERO,
            kd: Fix::ZERO,
        };
        let mut r1 = Vec::new();
        let mut r2 = Vec::new();
        let mut per = Vec::new();
        let mut lost = 0;
        for s in 0..4 {
            let (ys, _) = run(g, 100 + s, 0.0, 3.0, 1200, 600, sim);
            if ys.len() < 1200 {
                lost += 1;
                continue;
            }
            r1.push(rms(&ys[200..600]));
            r2.push(rms(&ys[700..1200]));
            per.push(period(&ys[400..1200]));
        }
        let m = |v: &Vec<f64>| v.iter().sum::<f64>() / v.len().max(1) as f64;
        println!(
            "RAMP K={k:.2} rms_early={:.2} rms_late={:.2} period={:.1} lost={lost}",
            m(&r1),
            m(&r2),
            m(&per)
        );
    }
}

fn relay(h: i32, eps: i32, seed: u64, speed: i16, sim: SimConfig) -> Option<(f64, f64, f64, f64)> {
    let mut w = World::new(long_line(40), sim, seed);
    let i = calibrated_robot(&mut w, config(), Pos::new(0, 0), Heading::North);
    let cal = w.robots[i].robot.calibration().unwrap();
    let mut t = RelayTuner::new(h, eps, 2, 5);
    let mut ys = Vec::new();
    let mut es = Vec::new();
    for _ in 0..3000 {
        let s = w.sense(i);
        let e = line_error(cal.apply(s.floor));
        es.push(e as f64);
        match t.update(e) {
            Relay::Drive(u) => w.drive_body(i, Wheels::from_linear_angular(i32::from(speed), u)),
            Relay::Done(c) => {
                let pose = w.robots[i].body.pose;
                let _ = pose;
                // amplitude of e over the last part
                let n = es.len();
                let tail = &es[n / 2..];
                let a = (tail.iter().cloned().fold(f64::MIN, f64::max)
                    - tail.iter().cloned().fold(f64::MAX, f64::min))
                    / 2.0;
                let _ = ys.len();
                return Some((c.gain.to_num(), c.period.to_num(), a, pose.y));
            }
            Relay::Failed => return None,
        }
        let pose = w.robots[i].body.pose;
        ys.push(pose.point(30.0, 0.0).0);
    }
    None
}

#[test]
#[ignore]
fn relay_variants() {
    let sim: SimConfig = std::env::var("NOISELESS")
        .map(|_| SimConfig {
            floor_noise: 0.0,
            slip: 0.0,
            ..SimConfig::default()
        })
        .unwrap_or_default();
    for h in [60, 120, 240] {
        for eps in [0, 10, 20, 40, 60] {
            let mut out = Vec::new();
            for s in 0..4 {
                if let Some(r) = relay(h, eps, 300 + s, 600, sim) {
                    out.push(r);
                }
            }
            let n = out.len().max(1) as f64;
            let kc = out.iter().map(|r| r.0).sum::<f64>() / n;
            let tc = out.iter().map(|r| r.1).sum::<f64>() / n;
            let a = out.iter().map(|r| r.2).sum::<f64>() / n;
            let d = out.iter().map(|r| r.3).sum::<f64>() / n;
            let corr = 4.0 * h as f64
                / (std::f64::consts::PI * (a * a - (eps * eps) as f64).max(1.0).sqrt());
            println!(
                "RELAY h={h} eps={eps} n={} kcrit={kc:.3} tcrit={tc:.1} a={a:.1} kcorr={corr:.3} dist={d:.0}",
                out.len()
            );
        }
    }
}

/// IAE (mm·s) of the sensor offset over `window` steps after each of four
/// step disturbances (lateral ±d, heading ±deg) applied to a robot following
/// a straight line; returns the four IAEs.
fn disturbance_iae(
    gains: Gains,
    seed: u64,
    d: f64,
    deg: f64,
    window: usize,
    sim: SimConfig,
) -> Vec<f64> {
    let mut w = World::new(long_line(40), sim, seed);
    let mut cfg = config();
    cfg.gains = gains;
    let i = calibrated_robot(&mut w, cfg, Pos::new(0, 0), Heading::North);
    w.order(i, Command::Move).unwrap();
    for _ in 0..100 {
        w.step();
    }
    let kicks = [(d, 0.0), (0.0, -deg), (-d, 0.0), (0.0, deg)];
    let mut out = Vec::new();
    for (lat, th) in kicks {
        let p = &mut w.robots[i].body.pose;
        p.x += lat;
        p.theta += f64::to_radians(th);
        let mut iae = 0.0;
        for _ in 0..window {
            let ev = w.step();
            let pose = w.robots[i].body.pose;
            let (sx, _) = pose.point(w.geometry.floor_forward_mm, 0.0);
            iae += sx.abs() * 0.01;
            if ev.iter().any(|e| e.robot == i) {
                iae += 1000.0;
                break;
            }
        }
        out.push(iae);
    }
    out
}

#[test]
#[ignore]
fn disturbance_sweep() {
    let kc: f64 = std::env::var("KC")
        .map(|s| s.parse().unwrap())
        .unwrap_or(1.886);
    let tc: f64 = std::env::var("TC")
        .map(|s| s.parse().unwrap())
        .unwrap_or(35.2);
    let seeds: u64 = std::env::var("SEEDS")
        .map(|s| s.parse().unwrap())
        .unwrap_or(30);
    let base: u64 = std::env::var("BASE")
        .map(|s| s.parse().unwrap())
        .unwrap_or(1000);
    let d: f64 = std::env::var("D")
        .map(|s| s.parse().unwrap())
        .unwrap_or(4.0);
    let deg: f64 = std::env::var("DEG")
        .map(|s| s.parse().unwrap())
        .unwrap_or(8.0);
    let win: usize = std::env::var("WIN")
        .map(|s| s.parse().unwrap())
        .unwrap_or(150);
    let sim = SimConfig::default();
    let tn = Fix::from_num(tc * 0.5);
    let tv = Fix::from_num(tc * 0.12);
    let fracs: Vec<u32> = (2..=24).map(|k| k * 5).collect();
    let mut costs: Vec<Vec<f64>> = Vec::new();
    let mut fails = Vec::new();
    for f in &fracs {
        let kr = Fix::from_num(kc * f64::from(*f) / 100.0);
        let g = Gains::from_times(kr, tn, tv);
        let mut nf = 0;
        let per: Vec<f64> = (0..seeds)
            .map(|s| {
                let v = disturbance_iae(g, base + s, d, deg, win, sim);
                nf += v.iter().filter(|x| **x >= 1000.0).count();
                v.iter()
                    .map(|x| if *x >= 1000.0 { *x - 1000.0 } else { *x })
                    .sum::<f64>()
                    / 4.0
            })
            .collect();
        costs.push(per);
        fails.push(nf);
    }
    let n = seeds as f64;
    let z = fracs.iter().position(|f| *f == 60).unwrap();
    for (k, f) in fracs.iter().enumerate() {
        let m = costs[k].iter().sum::<f64>() / n;
        let sd = (costs[k].iter().map(|c| (c - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let diff: Vec<f64> = (0..seeds as usize)
            .map(|s| costs[k][s] - costs[z][s])
            .collect();
        let dm = diff.iter().sum::<f64>() / n;
        let dsd = (diff.iter().map(|c| (c - dm).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        println!(
            "DIST {:.2}Kc kr={:.3} iae={m:.4} se={:.4} fails={} vsZN={dm:+.4}±{:.4}",
            f64::from(*f) / 100.0,
            kc * f64::from(*f) / 100.0,
            sd / n.sqrt(),
            fails[k],
            dsd / n.sqrt()
        );
    }
    let mut rng = 12345u64;
    let mut hist = vec![0u32; fracs.len()];
    for _ in 0..2000 {
        let idx: Vec<usize> = (0..seeds)
            .map(|_| {
                rng = rng
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                ((rng >> 33) % seeds) as usize
            })
            .collect();
        let mut best = (f64::INFINITY, 0);
        for k in 0..fracs.len() {
            if fails[k] > 0 {
                continue;
            }
            let m: f64 = idx.iter().map(|&s| costs[k][s]).sum();
            if m < best.0 {
                best = (m, k);
            }
        }
        hist[best.1] += 1;
    }
    for (k, f) in fracs.iter().enumerate() {
        if hist[k] > 0 {
            println!("BOOT argmin {:.2}Kc: {}", f64::from(*f) / 100.0, hist[k]);
        }
    }
}

fn walk(speed: i16, edges: usize, seed: u64, mut cfg: Config) -> Option<(f64, f64)> {
    use core_algo::behaviour::Event;
    use core_algo::geometry::Turn;
    cfg.node.node_spacing_steps = 776;
    let field = LineField::lattice(6, 6, 100.0, 12.0);
    let mut w = World::new(field, SimConfig::default(), seed);
    let i = calibrated_robot(&mut w, cfg, Pos::new(2, 2), Heading::North);
    w.order(i, Command::SetSpeed(speed)).unwrap();
    let mut node = Pos::new(2, 2);
    let mut heading = Heading::North;
    let (mut axle, mut sensor) = (Stats::default(), Stats::default());
    for k in 0..edges {
        let rel = relative_arms(&w, node, heading);
        let options: Vec<Turn> = [(1u8, None), (2, Some(Turn::Right)), (8, Some(Turn::Left))]
            .iter()
            .filter(|(b, _)| rel.bits() & b != 0)
            .map(|(_, t)| t.unwrap_or(Turn::UTurn))
            .collect();
        let pick = options[(k * 7 + seed as usize) % options.len().max(1)];
        let turn = if rel.bits() & 1 != 0 && pick == Turn::UTurn {
            None
        } else {
            Some(pick)
        };
        let turn = if options.is_empty() {
            Some(Turn::UTurn)
        } else {
            turn
        };
        if let Some(t) = turn {
            w.order(i, Command::Turn(t)).unwrap();
            if w.run_until_event(i, 400).map(|e| e.event) != Some(Event::Centred) {
                return None;
            }
            heading = heading.turned(t);
        }
        let run = drive_edge(&mut w, i, 2000);
        axle.merge(&run.axle);
        sensor.merge(&run.sensor);
        node = node.step(heading)?;
        let (at, facing, _) = where_is(&w, i);
        let truth = relative_arms(&w, node, heading);
        if run.end.map(|e| e.event) != Some(Event::NodeHit { arms: truth })
            || (at, facing) != (node, heading)
        {
            return None;
        }
    }
    Some((axle.rms(), sensor.rms()))
}

#[test]
#[ignore]
fn walk_sweep() {
    let kc: f64 = 1.886;
    let tc: f64 = 35.2;
    let seeds: u64 = std::env::var("SEEDS")
        .map(|s| s.parse().unwrap())
        .unwrap_or(20);
    let speed: i16 = std::env::var("SPEED")
        .map(|s| s.parse().unwrap())
        .unwrap_or(600);
    let tn = Fix::from_num(tc * 0.5);
    let tv = Fix::from_num(tc * 0.12);
    let fracs: Vec<u32> = (4..=20).map(|k| k * 5).collect();
    let mut costs = Vec::new();
    for f in &fracs {
        let kr = Fix::from_num(kc * f64::from(*f) / 100.0);
        let mut cfg = config();
        cfg.gains = Gains::from_times(kr, tn, tv);
        let mut fails = 0;
        let per: Vec<(f64, f64)> = (0..seeds)
            .map(|s| {
                walk(speed, 40, 500 + s, cfg).unwrap_or_else(|| {
                    fails += 1;
                    (f64::NAN, f64::NAN)
                })
            })
            .collect();
        costs.push(per.clone());
        let ok: Vec<&(f64, f64)> = per.iter().filter(|c| !c.0.is_nan()).collect();
        let n = ok.len() as f64;
        let ma = ok.iter().map(|c| c.0).sum::<f64>() / n;
        let ms = ok.iter().map(|c| c.1).sum::<f64>() / n;
        let sa = (ok.iter().map(|c| (c.0 - ma).powi(2)).sum::<f64>() / (n - 1.0)).sqrt() / n.sqrt();
        println!(
            "WALK v={speed} {:.2}Kc axle={ma:.4}±{sa:.4} sensor={ms:.4} fails={fails}",
            f64::from(*f) / 100.0
        );
    }
}

#[test]
#[ignore]
fn relay_amplitude() {
    for seed in 0..8u64 {
        let mut w = World::new(long_line(40), SimConfig::default(), 300 + seed);
        let i = calibrated_robot(&mut w, config(), Pos::new(0, 0), Heading::North);
        let cal = w.robots[i].robot.calibration().unwrap();
        let mut t = RelayTuner::new(120, 40, 2, 5);
        let (mut ys, mut th) = (Vec::new(), Vec::new());
        loop {
            let s = w.sense(i);
            let e = line_error(cal.apply(s.floor));
            match t.update(e) {
                Relay::Drive(u) => w.drive_body(i, Wheels::from_linear_angular(600, u)),
                Relay::Done(c) => {
                    let n = ys.len();
                    let tail = &ys[n * 2 / 5..];
                    let ttail = &th[n * 2 / 5..];
                    let amp = |v: &[f64]| {
                        (v.iter().cloned().fold(f64::MIN, f64::max)
                            - v.iter().cloned().fold(f64::MAX, f64::min))
                            / 2.0
                    };
                    println!(
                        "LIMIT seed={seed} kc={:.3} tc={:.1} sensor_amp_mm={:.2} sensor_rms={:.2} heading_amp_deg={:.2}",
                        c.gain,
                        c.period,
                        amp(tail),
                        rms(tail),
                        amp(ttail)
                    );
                    break;
                }
                Relay::Failed => {
                    println!("failed");
                    break;
                }
            }
            let pose = w.robots[i].body.pose;
            ys.push(pose.point(30.0, 0.0).0);
            th.push((pose.theta - std::f64::consts::FRAC_PI_2).to_degrees());
        }
    }
}
