//! The arrays and names the output files share: vectors and tensors padded to 3D, the
//! plane-strain σ_zz, the axis letters and stress components of the columns, the names
//! of the reference solution's columns and arrays, VTK's vertex order.
use impact_core::Vector;
use impact_io::vtu::CellType;

pub(super) fn pad3<const D: usize>(v: &Vector<D>) -> [f64; 3] {
    let mut out = [0.0; 3];
    for l in 0..D.min(3) {
        out[l] = v[l];
    }
    out
}

pub(super) fn tensor9<const D: usize>(t: &impact_core::Tensor<D>) -> [f64; 9] {
    let mut full = [0.0; 9];
    for r in 0..D {
        for c in 0..D {
            full[3 * r + c] = t[(r, c)];
        }
    }
    full
}

/// The 3×3 tensor with the plane-strain `σ_zz` in its zz slot when `material` is given.
pub(super) fn with_zz<const D: usize>(
    mut full: [f64; 9],
    t: &impact_core::Tensor<D>,
    material: Option<impact_core::LinearElastic>,
) -> [f64; 9] {
    if let Some(m) = material {
        full[8] = m.out_of_plane_stress(t);
    }
    full
}

/// Axis letters of columns and arrays.
pub(super) const AXES: [&str; 3] = ["x", "y", "z"];

/// The stress components a `d`-dimensional run writes: (index in the row-major 3×3
/// tensor, suffix); Voigt order.
pub(super) fn stress_components(d: usize) -> &'static [(usize, &'static str)] {
    match d {
        1 => &[(0, "xx")],
        2 => &[(0, "xx"), (4, "yy"), (8, "zz"), (1, "xy")],
        _ => &[
            (0, "xx"),
            (4, "yy"),
            (8, "zz"),
            (5, "yz"),
            (2, "xz"),
            (1, "xy"),
        ],
    }
}

/// The names of the reference solution's columns and arrays along axis `a`:
/// `reference_<measure>_aa` and `reference_velocity_a` (the reference *solution*; the
/// samples' reference *position* is `reference_position`).
pub(super) fn reference_names(measure: &str, a: usize) -> (String, String) {
    let l = AXES[a.min(2)];
    (
        format!("reference_{measure}_{l}{l}"),
        format!("reference_velocity_{l}"),
    )
}

/// Vertex order of a grid cell as VTK wants it, from the grid's local vertex numbering
/// (bit `l` of `a` set: the high side along axis `l`): line 0 1; quad counter-clockwise;
/// hexahedron (VTK type 12) the bottom face counter-clockwise, then the top face above it.
pub(super) fn vtk_order(d: usize) -> (&'static [usize], CellType) {
    match d {
        1 => (&[0, 1], CellType::Line),
        2 => (&[0, 1, 3, 2], CellType::Quad),
        _ => (&[0, 1, 3, 2, 4, 5, 7, 6], CellType::Hexahedron),
    }
}
