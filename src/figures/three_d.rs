//! The 3D figures (issue 24): the block impact (`block`: σₓₓ on the mid-plane through the
//! impact and along the line through it, the three methods; with `--full` against the
//! converged reference, which takes minutes to compute once) and Lamb's problem (`lamb`:
//! the surface traces of the three methods at the scene's resolution against Pekeris'
//! exact solution; `impact bench lamb` runs the three-grid ladder).
use super::paper::{three_methods, Shipped};
use super::{Entry, Target};
use crate::plots::map_figure;
use anyhow::Result;
use impact_core::method::MethodKind;
use impact_core::{Problem, Scene, Vector};
use impact_io::plot::Stacked;

/// The block impact: maps of the plane through the impact above the profiles.
pub fn block(target: &Target) -> Result<Entry> {
    let block = Shipped::<3>::run_with("block", target.progress, target.full, three_methods)?;
    let grid = &block.problem.grid;
    let line = impact_core::line::MeasureLine::of(&block.problem);
    let plane = crate::plane::MapPlane::of(grid, &line).expect("internal: 3D has a plane");
    let average = |lo: &Vector<2>, hi: &Vector<2>, t: f64| {
        let (lo, hi) = plane.lift(grid, lo, hi);
        block
            .reference
            .as_ref()
            .map_or(f64::NAN, |r| r.averages(&lo, &hi, t).0)
    };
    let reference = block.reference.as_ref().map(|r| {
        (
            crate::plots::reference_label(r),
            &average as &dyn Fn(&Vector<2>, &Vector<2>, f64) -> f64,
        )
    });
    let times = &block.problem.output_times;
    let maps = map_figure(
        &plane.grid(grid),
        &plane.describe(grid),
        &block.collected,
        reference,
        times,
    )
    .ok_or_else(|| anyhow::anyhow!("the block runs kept no maps"))?;
    let mut profiles = block.profile_figure();
    profiles.columns = times.len().max(1);
    profiles.aspect = 0.62;
    let image = target.save("block_impact", Stacked(maps, profiles))?;
    let mut lines = block.numbers();
    lines.insert(
        0,
        match &block.reference {
            Some(r) => format!("reference: {}", r.describe()),
            None => "reference: none in the reduced settings (--full computes the converged \
                     DGMPM reference 4x finer, 1.3 M cells)"
                .into(),
        },
    );
    Ok(Entry {
        name: "block".into(),
        title: "3D block impact: σₓₓ on the mid-plane through the impact, and along its axis"
            .into(),
        images: vec![image],
        command: format!("{}   # data: impact run block", target.command),
        numbers: lines,
        seconds: 0.0,
    })
}

/// Lamb's problem: the surface traces at the scene's resolution.
pub fn lamb(target: &Target) -> Result<Entry> {
    let scene = Scene::builtin("lamb").expect("internal: a shipped scene");
    let problem = Problem::<3>::from_scene(&scene)?;
    let load = crate::lamb::lamb_load(&problem)?;
    let points = crate::lamb::receivers(&scene, &load, &problem)?;
    let h = problem.grid.min_spacing();
    let mut finest = Vec::new();
    let mut lines = vec![format!(
        "exact: Pekeris (1955) convolved with the smooth ramp, averaged over the patch; \
         grid {:?} cells, h = {h} m",
        scene.domain.cells
    )];
    for kind in MethodKind::ALL {
        let recorded = crate::lamb::traces(&problem, scene.method_config(kind), &load, &points)?;
        for trace in &recorded {
            let row = crate::lamb_study::row(kind.name(), scene.domain.cells[0], h, trace, &load);
            lines.push(format!(
                "{}: r = {:.3} m, L2 of w {:.3e}, of u_r {:.3e}; P {:+.2} cells, Rayleigh {:+.2} cells",
                row.method,
                row.r,
                row.l2_vertical,
                row.l2_radial,
                row.p_cells.unwrap_or(f64::NAN),
                row.rayleigh_cells.unwrap_or(f64::NAN)
            ));
        }
        finest.push((kind.name().to_string(), recorded));
    }
    let image = target.save("lamb_traces", crate::lamb_study::figure(&finest))?;
    Ok(Entry {
        name: "lamb".into(),
        title: "Lamb's problem: surface displacement traces against Pekeris' solution".into(),
        images: vec![image],
        command: format!("{}   # ladder: impact bench lamb", target.command),
        numbers: lines,
        seconds: 0.0,
    })
}
