use pbdda::world::World;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let model = pbdda::scene::load(std::path::Path::new(&args[1])).unwrap();
    let mut w = World::new(model);
    for i in 0..4000 {
        let r = w.step().unwrap();
        let b = &w.bodies[1];
        let v2 = b.velocity[0].powi(2) + b.velocity[1].powi(2);
        if i % 100 == 0 || (i > 880 && i < 920 && i % 5 == 0) {
            let pn: f64 = r.contacts.iter().map(|c| c.normal_force).sum();
            let g0: Vec<String> = r.contacts.iter().map(|c| format!("{:.2e}/{:.2e}", c.gap, c.normal_force)).collect();
            println!("step {} t {:.3} y {:.6} r {:.9} E {:.6} om {:.3e} it {} pn {:.1} {:?}", r.step, r.time, b.centroid.y, b.centroid.norm(), 0.5*v2 + 10.0*b.centroid.y, b.velocity[2], r.inner_iterations, pn, g0);
        }
    }
}
