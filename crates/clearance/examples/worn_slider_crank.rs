//! A slider-crank at 600 rpm whose rod–slider joint has 0.5 mm of clearance and wears:
//! 0.5 s of motion, then the peak contact force and the deepest wear.
//!
//! `cargo run --release -p clearance --example worn_slider_crank`

use clearance::contact::LineOfCentres;
use clearance::multibody::*;
use clearance::{Ambrosio, ClearanceJointBuilder, JointSide, LankaraniNikravesh, Material};
use clearance::{WearParams, WornClearanceForce};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (r, l, w) = (0.1, 0.35, 20.0 * std::f64::consts::PI);
    let mut model = Model::new();
    let crank = model.add_body(Body::new("crank", 1.0, 1e-3, [r / 2.0, 0.0, 0.0]))?;
    // The rod turns as a rigid slider-crank's would at t = 0 (B is free now, so say it).
    let rod = Body::new("rod", 2.0, 0.02, [r + l / 2.0, 0.0, 0.0]);
    let rod = model.add_body(rod.with_velocity([0.0, 0.5 * r * w, -r * w / l]))?;
    let slider = model.add_body(Body::new("slider", 3.0, 0.01, [r + l, 0.0, 0.0]))?;
    let (o, a) = (Anchor::ground(0.0, 0.0), Anchor::on(crank, r / 2.0, 0.0));
    model.add_revolute("O", o, Anchor::on(crank, -r / 2.0, 0.0))?;
    model.add_revolute("A", a, Anchor::on(rod, -l / 2.0, 0.0))?;
    let (slide, lock) = (Anchor::on(slider, 0.0, 0.0), RotationLock::At(0.0));
    model.add_prismatic("guide", o, [1.0, 0.0], slide, lock)?;
    let crank_angle = DriveTarget::Coordinate(crank, Coordinate::Theta);
    let turn = Ramp::new(0.0, w);
    model.add_driver("motor", crank_angle, Box::new(turn))?;
    let gravity = Gravity::new(&model, [0.0, -9.81]);
    let mut system = System::new(model)?;
    system.add_element(Box::new(gravity));

    // Joint B: a 10 mm steel hole at the rod's end around a 9.5 mm pin on the slider.
    let steel = Material::new(207e9, 0.3)?;
    let bearing = JointSide::on(rod, [l / 2.0, 0.0], 0.010, steel);
    let pin = JointSide::on(slider, [0.0, 0.0], 0.0095, steel);
    let wear = WearParams::archard(1.8e-13).with_hinge_width(0.02);
    let b = ClearanceJointBuilder::new("B", bearing, pin, LankaraniNikravesh::new(0.9)?)
        .friction(Ambrosio::new(0.1, 1e-4, 1e-3)?)
        .contact_model(LineOfCentres)
        .wearing(&wear)?;
    let b = system.add_element(Box::new(b));

    let (q, qd) = system.initial_guess();
    let start = system.assemble(0.0, &q, &qd)?;
    let run = system.simulate(&start, &SimulationOptions::until(0.5), &mut ())?;
    let b = system.element::<WornClearanceForce>(b).ok_or("B is gone")?;
    let (force, steps) = (b.peak_normal_force(), run.statistics.steps);
    println!("{steps} steps; peak contact force at B: {force:.0} N");
    let wear = b.stage_wear().ok_or("B does not wear")?.max_depth();
    println!("deepest wear at B after 5 turns: {wear:.3e} m");
    Ok(())
}
