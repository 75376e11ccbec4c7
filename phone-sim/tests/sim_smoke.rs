use core_algo::explore::NearestFrontier;
use core_algo::team::RobotId;
use phone_sim::field;
use phone_sim::sim::robot::BoxedStrategy;
use phone_sim::sim::{SimConfig, Simulation};

#[test]
fn demo_explores() {
    let f = field::generate::open(5, 5, 0);
    let mut sim = Simulation::new(&f, 2, |_: RobotId| BoxedStrategy(Box::new(NearestFrontier)), SimConfig::default()).unwrap();
    let out = sim.run();
    eprintln!("{out:#?}");
    for fw in sim.firmware() {
        eprintln!("{:?} {:?} {:?}", fw.agent().mode(), fw.agent().pose(), fw.stats());
    }
    assert!(out.complete);
}
