//! Lamb's problem (issue 24): every method's surface traces on the shipped `lamb` scene at
//! half and at its own resolution (18×18×12 and 36×36×24 cells) against Pekeris' exact
//! solution ([`impact_core::exact::Lamb`]): the traces' L2 errors shrink under
//! refinement, the P onset arrives within two cells of the exact one and the Rayleigh
//! pulse within two (MPM with linear hats at one point per cell: 2.5; it lags by 1.0-2.2
//! cells: its own phase error, growing with the distance and independent of the time step
//! and of the stress update, `mpm_rayleigh_lag_is_its_phase_error`; docs/methods.md).
use impact::lamb::{lamb_load, onset, p_level, receivers, relative_l2, steepest, traces};
use impact_core::method::MethodKind;
use impact_core::{Problem, Scene};

#[test]
fn surface_traces_converge_and_arrive_on_time() {
    let scene = Scene::builtin("lamb").unwrap();
    for kind in MethodKind::ALL {
        let mut errors = Vec::new();
        for factor in [0.5, 1.0] {
            let mut s = scene.clone();
            for n in &mut s.domain.cells {
                *n = (*n as f64 * factor) as usize;
            }
            let problem = Problem::<3>::from_scene(&s).unwrap();
            let load = lamb_load(&problem).unwrap();
            let points = receivers(&s, &load, &problem).unwrap();
            let h = problem.grid.min_spacing();
            let recorded = traces(&problem, s.method_config(kind), &load, &points).unwrap();
            let level: Vec<f64> = recorded
                .iter()
                .map(|t| relative_l2(&t.vertical, &t.vertical_exact))
                .collect();
            errors.push(level);
            if factor < 1.0 {
                continue;
            }
            let (p_limit, r_limit) = if kind == MethodKind::Mpm {
                (2.0, 2.5)
            } else {
                (2.0, 2.0)
            };
            for t in &recorded {
                let level = p_level(&t.radial_exact);
                let e = &load.exact;
                let p = (onset(&t.t, &t.radial, level).unwrap()
                    - onset(&t.t, &t.radial_exact, level).unwrap())
                    * e.pressure_speed()
                    / h;
                let r = (steepest(&t.t, &t.vertical).unwrap()
                    - steepest(&t.t, &t.vertical_exact).unwrap())
                    * e.rayleigh_speed()
                    / h;
                assert!(
                    p.abs() <= p_limit,
                    "{kind:?} at r = {}: P off by {p} cells",
                    t.r
                );
                assert!(
                    r.abs() <= r_limit,
                    "{kind:?} at r = {}: R off by {r} cells",
                    t.r
                );
            }
        }
        for (k, (coarse, fine)) in errors[0].iter().zip(&errors[1]).enumerate() {
            assert!(
                fine < coarse && *fine < 0.3,
                "{kind:?}, receiver {k}: L2 of w {coarse} → {fine}"
            );
        }
    }
}

/// Why MPM (linear hats, one point per cell) is allowed 2.5 cells on the Rayleigh arrival:
/// its lag is its own phase error, not the readout. On the shipped grid (36 cells along x)
/// the lag grows with the distance travelled (1.5, 1.9, 2.2 cells at r ≈ 0.38, 0.58, 0.78 m),
/// and it stays within 0.3 cells when the Courant number is halved (so it is not USL's
/// O(Δt) velocity lag) or the stress is updated after the grid update (MUSL). DGMPM and FEM
/// read their traces at the same depth (half a cell below the surface: a point, an element
/// centre) with the same pick and arrive within 0.73 cells (docs/methods.md).
#[test]
fn mpm_rayleigh_lag_is_its_phase_error() {
    use impact_core::method::StressUpdate;
    let s = Scene::builtin("lamb").unwrap();
    let problem = Problem::<3>::from_scene(&s).unwrap();
    let load = lamb_load(&problem).unwrap();
    let points = receivers(&s, &load, &problem).unwrap();
    let h = problem.grid.min_spacing();
    let lag = |courant: f64, update: StressUpdate| -> Vec<f64> {
        let mut c = s.method_config(MethodKind::Mpm);
        c.courant = courant;
        c.mpm_mut().unwrap().stress_update = update;
        let recorded = traces(&problem, c, &load, &points).unwrap();
        recorded
            .iter()
            .map(|t| {
                (steepest(&t.t, &t.vertical).unwrap() - steepest(&t.t, &t.vertical_exact).unwrap())
                    * load.exact.rayleigh_speed()
                    / h
            })
            .collect()
    };
    let base = lag(0.5, StressUpdate::Usl);
    let half = lag(0.25, StressUpdate::Usl);
    let musl = lag(0.5, StressUpdate::Musl);
    println!("MPM Rayleigh lag (cells): C 0.5 {base:.2?}, C 0.25 {half:.2?}, MUSL {musl:.2?}");
    assert!(base.windows(2).all(|w| w[1] > w[0]), "{base:?}");
    assert!(base[0] > 0.5, "{base:?}");
    for other in [&half, &musl] {
        for (a, b) in base.iter().zip(other.iter()) {
            assert!((a - b).abs() < 0.3, "{base:?} {other:?}");
        }
    }
}
