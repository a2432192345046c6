//! The cell layouts give every cell the very blocks formed from its own points (bit for
//! bit: the shape values and gradients of `shapes`, the volume weights of
//! `cell_volume_weights`, the mapping weights and lumped masses of
//! `cell_mapping_weights`), on a uniform seeding (few layouts) and on a randomly jittered
//! one (a layout per cell), in 1D, 2D and 3D.
use super::*;
use impact_core::method::MethodKind;
use impact_core::{Problem, Scene};

/// Every block `blocks` keeps of every cell, from its own points, against the table's.
fn check_table<const D: usize>(
    label: &str,
    grid: &Grid<D>,
    points: &MaterialPoints<D>,
    points_per_cell: usize,
) -> usize {
    let n = Grid::<D>::NODES_PER_CELL;
    let blocks = Blocks {
        gradient: true,
        volume: true,
        mapping: true,
    };
    let table = CellLayouts::new(grid, points, points_per_cell, blocks).unwrap();
    let (shape, gradient) = shapes(grid, points).unwrap();
    let cells = points.len() / points_per_cell;
    let per_cell = points_per_cell * n;
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let vector_bits = |v: &[Vector<D>]| {
        v.iter()
            .flat_map(|v| v.iter().map(|x| x.to_bits()))
            .collect::<Vec<_>>()
    };
    let mut k = vec![Vector::<D>::zeros(); (n - 1) * n];
    let (mut w, mut m) = (vec![0.0; per_cell], vec![0.0; n]);
    for c in 0..cells {
        let l = table.layout_of(c);
        let (s, g) = (
            &shape[c * per_cell..(c + 1) * per_cell],
            &gradient[c * per_cell..(c + 1) * per_cell],
        );
        let own = c * points_per_cell..(c + 1) * points_per_cell;
        cell_volume_weights::<D>(s, g, &points.volume[own.clone()], &mut k);
        cell_mapping_weights::<D>(s, &points.mass[own], &mut w, &mut m);
        assert_eq!(bits(table.shape_of(l)), bits(s), "{label}: cell {c} shape");
        assert_eq!(
            vector_bits(table.gradient_of(l)),
            vector_bits(g),
            "{label}: cell {c} gradients"
        );
        assert_eq!(
            vector_bits(table.volume_weights_of(l)),
            vector_bits(&k),
            "{label}: cell {c} volume weights"
        );
        assert_eq!(
            bits(table.mapping_weights_of(l)),
            bits(&w),
            "{label}: cell {c} mapping weights"
        );
        assert_eq!(bits(table.mass_of(l)), bits(&m), "{label}: cell {c} masses");
    }
    println!(
        "{label}: {} layouts for {cells} cells",
        table.layout_count()
    );
    table.layout_count()
}

/// The builtin scene `name` on `cells` at `points_per_cell`: its grid and points.
fn seeded<const D: usize>(
    name: &str,
    cells: &[usize],
    points_per_cell: usize,
) -> (Grid<D>, MaterialPoints<D>) {
    let mut scene = Scene::builtin(name).unwrap();
    scene.domain.cells = cells.to_vec();
    let problem = Problem::<D>::from_scene(&scene).unwrap();
    let mut config = scene.method_config(MethodKind::Dgmpm);
    config.points_per_cell = points_per_cell;
    let points = problem.material_points(&problem.grid, &config).unwrap();
    (problem.grid, points)
}

/// Every point moved to a random place strictly inside its cell (xorshift, fixed seed)
/// and its mass and volume scaled by a random factor in [0.5, 1.5).
fn jitter<const D: usize>(grid: &Grid<D>, points: &mut MaterialPoints<D>, per_cell: usize) {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for p in 0..points.len() {
        let idx = grid.cell_multi_index(p / per_cell);
        for l in 0..D {
            let u = 0.05 + 0.9 * uniform();
            points.reference[p][l] = grid.origin[l] + (idx[l] as f64 + u) * grid.spacing[l];
        }
        let scale = 0.5 + uniform();
        points.mass[p] *= scale;
        points.volume[p] *= scale;
    }
}

#[test]
fn layouts_hold_each_cells_blocks() {
    // uniform seeding: few layouts
    let (grid, points) = seeded::<2>("plate", &[40, 30], 4);
    assert!(check_table("plate 4 ppc", &grid, &points, 4) <= 256);
    let (grid, points) = seeded::<1>("bar", &[100], 2);
    assert!(check_table("bar 2 ppc", &grid, &points, 2) <= 16);
    let (grid, points) = seeded::<3>("block", &[6, 4, 4], 8);
    assert!(check_table("block 8 ppc", &grid, &points, 8) <= 96);
    // irregular seeding: a layout per cell
    let (grid, mut points) = seeded::<2>("plate", &[20, 15], 4);
    jitter(&grid, &mut points, 4);
    assert_eq!(check_table("jittered plate", &grid, &points, 4), 300);
    let (grid, mut points) = seeded::<3>("block", &[4, 3, 3], 8);
    jitter(&grid, &mut points, 8);
    assert_eq!(check_table("jittered block", &grid, &points, 8), 36);
}
