//! The core types are dimension-generic: a `D = 3` instantiation of the grid, the points,
//! the material and its wave speeds compiles and behaves (no 3D method exists yet).
use impact_core::material::{LinearElastic, Svk};
use impact_core::points::MaterialPoints;
use impact_core::{Grid, Tensor, Vector};

#[test]
fn three_dimensional_core_types_work() {
    let grid = Grid::<3> {
        origin: Vector::<3>::zeros(),
        spacing: Vector::<3>::new(0.5, 0.25, 0.125),
        cells: [4, 3, 2],
    };
    assert_eq!(grid.cell_count(), 24);
    assert_eq!(Grid::<3>::NODES_PER_CELL, 8);
    assert_eq!(Grid::<3>::tangent_axes(1).collect::<Vec<_>>(), vec![0, 2]);
    assert_eq!(grid.face_count(2), 4 * 3 * 3);
    let x = Vector::<3>::new(1.3, 0.6, 0.2);
    let (c, xi) = grid.locate(&x).unwrap();
    let mut s = [0.0; 8];
    let mut g = [Vector::<3>::zeros(); 8];
    grid.shape(&xi, &mut s, &mut g);
    assert!((s.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    let rebuilt: Vector<3> = (0..8)
        .map(|a| grid.vertex_position(grid.vertex_of(c, a)) * s[a])
        .sum();
    assert!((rebuilt - x).norm() < 1e-12, "trilinear shapes reproduce x");
    let points = MaterialPoints::regular(&grid, 2, 7800.0);
    assert_eq!(points.len(), 24 * 8);
    let mass: f64 = points.mass.iter().sum();
    assert!((mass - 7800.0 * 2.0 * 0.75 * 0.25).abs() < 1e-9);
    // a P wave in 3D is in uniaxial strain, as in plane strain: c_p = sqrt((λ+2μ)/ρ)
    let steel = LinearElastic::new(2e11, 0.3, 7800.0);
    let (c3, c2) = (steel.p_wave_speed::<3>(), steel.p_wave_speed::<2>());
    assert!((c3 - c2).abs() < 1e-9 * c2);
    // SVK at F = 1: the largest acoustic wave speed is c_p, also in 3D (eigenvalue range)
    let svk = Svk::new(steel);
    let speed = svk.max_wave_speed(&Tensor::<3>::identity());
    assert!((speed - c3).abs() < 1e-6 * c3, "{speed} vs {c3}");
}
