//! The guard's state check (`Method::check_finite`): a NaN or an infinity in any point's
//! stress, velocity or position is found, at that point, in both frames (the total
//! Lagrangian frame tests the values alone, `x·0` summed; the updated one every check of
//! `point_failure`), and a finite state passes.
use impact_core::method::{MethodKind, MpmFrame};
use impact_core::{Method, Problem};
use impact_mpm::Mpm;

use crate::decomposed::{options, scene};

#[test]
fn a_non_finite_value_is_found_at_its_point_in_both_frames() {
    let plate = scene("plate");
    let problem = Problem::<2>::from_scene(&plate).unwrap();
    for frame in [MpmFrame::TotalLagrangian, MpmFrame::UpdatedLagrangian] {
        let mut config = plate.method_config(MethodKind::Mpm);
        options(&mut config).frame = frame;
        let fresh = Mpm::<2>::new(&problem, config).unwrap();
        assert!(
            fresh.check_finite().is_ok(),
            "{frame:?}: a finite state fails"
        );
        let count = fresh.state.points.len();
        for (k, value) in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY]
            .into_iter()
            .enumerate()
        {
            for field in 0..3 {
                // a point in the middle of the body, another for each case
                let bad = count / 2 + 7 * (3 * k + field);
                let mut m = fresh.clone();
                let points = &mut m.state.points;
                match field {
                    0 => points.stress[bad][(1, 0)] = value,
                    1 => points.velocity[bad][1] = value,
                    _ => points.position[bad][0] = value,
                }
                let found = m.check_finite().expect_err("a non-finite value passed");
                assert_eq!(
                    found.place, m.state.points.reference[bad],
                    "{frame:?}, field {field}, {value}: found at another point"
                );
                assert!(found.reason.contains("non-finite"), "{}", found.reason);
            }
        }
    }
}
