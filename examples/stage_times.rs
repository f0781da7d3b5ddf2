use std::time::Instant;
use mbfx::session::run::{Simulation, RunSpec};
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let end: f64 = std::env::args().nth(2).unwrap().parse().unwrap();
    let interp = std::env::args().nth(3).as_deref() == Some("interp");
    let text = std::fs::read_to_string(&path).unwrap();
    let mut best = [f64::MAX; 6];
    for _ in 0..30 {
        let t0 = Instant::now();
        let read = mbfx::model::read_model(&text);
        let t1 = Instant::now();
        let a = mbfx::session::analyze_model_with(&read.model, mbfx::session::DimRequest::Auto, interp).ok().unwrap();
        let t2 = Instant::now();
        drop(a);
        let mut spec = RunSpec::new(end, 0.01);
        if interp { spec.engine = mbfx::session::run::Engine::Interp; }
        let t3 = Instant::now();
        let mut sim = Simulation::new(&text, spec, &[("y".into(), "DX(201)".into())]).ok().unwrap();
        let t4 = Instant::now();
        let (_s, e) = sim.run(&mut |_r| Ok(()));
        assert!(e.is_none());
        let t5 = Instant::now();
        let d = [t1-t0, t2-t1, t3-t2, t4-t3, t5-t4, t5-t0];
        for k in 0..6 { best[k] = best[k].min(d[k].as_secs_f64()*1e3); }
    }
    println!("read {:.3} analyze {:.3} drop {:.3} simnew {:.3} run {:.3} ms", best[0], best[1], best[2], best[3], best[4]);
}
