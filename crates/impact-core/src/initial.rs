//! Initial states: at rest (the paper's scenes), a standing P mode with an exact solution
//! ([`crate::exact::StandingWave`]), or fields given by formulas of the reference position.
//!
//! A formula is a string in `x` (and `y` in 2D, `y`, `z` in 3D), in m, with `+ - * / ^`, parentheses,
//! `sin cos tan exp ln log10 sqrt abs` and the constants `PI` (or `π`) and `E`, parsed by
//! the `exmex` crate: e.g. `velocity = ["0.5*sin(PI*x/6)"]`. The methods evaluate it at
//! their velocity and stress carriers (material points; FEM nodes for the velocity) once,
//! before the first step.
use crate::exact::{PlaneWave, StandingWave};
use crate::{Tensor, Vector};
use exmex::prelude::*;

/// A parsed formula of `x` (and `y`).
#[derive(Clone)]
pub struct Formula {
    text: String,
    expr: FlatEx<f64>,
    /// For each variable of `expr` (alphabetical order), the coordinate it reads.
    axes: Vec<usize>,
}

impl std::fmt::Debug for Formula {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Formula({:?})", self.text)
    }
}

impl PartialEq for Formula {
    fn eq(&self, other: &Self) -> bool {
        self.text == other.text
    }
}

impl Formula {
    /// Parse `text` as a formula of the first `dim` coordinates (`x`, then `y`, then `z`). The error
    /// says what is wrong, for the caller to name the field.
    pub fn parse(text: &str, dim: usize) -> Result<Self, String> {
        let plain = expand_exponents(text)?;
        let expr = exmex::parse::<f64>(&plain).map_err(|e| format!("not a formula: {e}"))?;
        let names = ["x", "y", "z"];
        let mut axes = Vec::new();
        for var in expr.var_names() {
            match names[..dim].iter().position(|n| n == var) {
                Some(axis) => axes.push(axis),
                None => {
                    return Err(format!(
                        "unknown variable `{var}` (allowed: {}; constants PI and E)",
                        names[..dim].join(", ")
                    ))
                }
            }
        }
        Ok(Self {
            text: text.to_string(),
            expr,
            axes,
        })
    }

    /// The value at `position` (NaN where the formula is undefined, e.g. `ln` of a
    /// negative number; validation refuses those).
    pub fn eval(&self, position: &[f64]) -> f64 {
        // up to three coordinates (3D: `x`, `y` and `z`)
        let mut values = [0.0; 3];
        for (slot, &axis) in values.iter_mut().zip(&self.axes) {
            *slot = position[axis];
        }
        self.expr
            .eval(&values[..self.axes.len()])
            .unwrap_or(f64::NAN)
    }

    /// The source text.
    pub fn text(&self) -> &str {
        &self.text
    }
}

/// `text` with every number in scientific notation (`2.5e11`, `1E-3`) written out in plain
/// decimals (exmex reads no exponent; Rust's `f64` display never uses one and reads back
/// to the same value).
fn expand_exponents(text: &str) -> Result<String, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < chars.len() {
        let in_name = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
        if !(chars[i].is_ascii_digit() || chars[i] == '.') || in_name {
            out.push(chars[i]);
            i += 1;
            continue;
        }
        let start = i;
        while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
            i += 1;
        }
        let mut end = i;
        if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
            let mut j = i + 1;
            if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                j += 1;
            }
            if j < chars.len() && chars[j].is_ascii_digit() {
                while j < chars.len() && chars[j].is_ascii_digit() {
                    j += 1;
                }
                end = j;
            }
        }
        let literal: String = chars[start..end].iter().collect();
        if end > i {
            let value: f64 = literal
                .parse()
                .map_err(|_| format!("not a number: `{literal}`"))?;
            out.push_str(&format!("{value}"));
        } else {
            out.push_str(&literal);
        }
        i = end;
    }
    Ok(out)
}

/// The state at `t = 0`.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum InitialState {
    /// At rest, unstressed.
    #[default]
    Rest,
    /// The standing P mode (exact solution with `symmetry` edges).
    StandingWave(StandingWave),
    /// A travelling plane P or S pulse (exact until the boundaries' influence arrives):
    /// velocity, stress and (FEM) displacement at `t = 0`.
    PlaneWave(PlaneWave),
    /// Velocity components and stress components (`xx` in 1D; `xx, yy, xy` in 2D;
    /// `xx, yy, zz, yz, xz, xy` in 3D: [`stress_components`]) by formula; a missing list
    /// is zero.
    Formula {
        /// One formula per velocity component (m/s), or none.
        velocity: Vec<Formula>,
        /// Stress components (Pa), or none.
        stress: Vec<Formula>,
    },
}

impl InitialState {
    /// Whether the body starts at rest and unstressed.
    pub fn is_rest(&self) -> bool {
        *self == InitialState::Rest
    }

    /// Whether the state has a nonzero initial stress (which FEM, whose state is its
    /// displacement, and the large-strain model cannot take).
    pub fn has_stress(&self) -> bool {
        matches!(self, InitialState::Formula { stress, .. } if !stress.is_empty())
    }

    /// Velocity at reference position `x`.
    pub fn velocity<const D: usize>(&self, x: &Vector<D>) -> Vector<D> {
        match self {
            InitialState::Rest => Vector::<D>::zeros(),
            InitialState::StandingWave(w) => {
                let v = w.velocity(std::array::from_fn(|l| if l < D { x[l] } else { 0.0 }), 0.0);
                Vector::<D>::from_fn(|k, _| v[k])
            }
            InitialState::PlaneWave(w) => {
                let v = w.velocity(pad(x), 0.0);
                Vector::<D>::from_fn(|k, _| v[k])
            }
            InitialState::Formula { velocity, .. } => {
                Vector::<D>::from_fn(|k, _| velocity.get(k).map_or(0.0, |f| f.eval(x.as_slice())))
            }
        }
    }

    /// Displacement at reference position `x`: zero but for the plane wave (FEM, whose
    /// state is its displacement, takes the wave's stress through it).
    pub fn displacement<const D: usize>(&self, x: &Vector<D>) -> Vector<D> {
        match self {
            InitialState::PlaneWave(w) => {
                let u = w.displacement(pad(x), 0.0);
                Vector::<D>::from_fn(|k, _| u[k])
            }
            _ => Vector::<D>::zeros(),
        }
    }

    /// Stress at reference position `x` (the standing mode starts unstressed).
    pub fn stress<const D: usize>(&self, x: &Vector<D>) -> Tensor<D> {
        let mut sigma = Tensor::<D>::zeros();
        if let InitialState::PlaneWave(w) = self {
            let voigt = w.stress(pad(x), 0.0);
            for (k, &(i, j)) in stress_components(3).iter().enumerate() {
                if i < D && j < D {
                    sigma[(i, j)] = voigt[k];
                    sigma[(j, i)] = voigt[k];
                }
            }
        }
        if let InitialState::Formula { stress, .. } = self {
            let value = |k: usize| stress.get(k).map_or(0.0, |f| f.eval(x.as_slice()));
            for (k, &(i, j)) in stress_components(D).iter().enumerate() {
                sigma[(i, j)] = value(k);
                sigma[(j, i)] = value(k);
            }
        }
        sigma
    }
}

/// `x` with zeros beyond dimension `D`.
fn pad<const D: usize>(x: &Vector<D>) -> [f64; 3] {
    std::array::from_fn(|l| if l < D { x[l] } else { 0.0 })
}

/// The stress components `(i, j)` a scene's `initial.stress` lists in dimension `dim`:
/// `[xx]`, `[xx, yy, xy]`, `[xx, yy, zz, yz, xz, xy]` (Voigt order).
pub fn stress_components(dim: usize) -> &'static [(usize, usize)] {
    match dim {
        1 => &[(0, 0)],
        2 => &[(0, 0), (1, 1), (0, 1)],
        _ => &[(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)],
    }
}

/// Names of [`stress_components`].
pub fn stress_component_names(dim: usize) -> &'static str {
    match dim {
        1 => "[xx]",
        2 => "[xx, yy, xy]",
        _ => "[xx, yy, zz, yz, xz, xy]",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formulas_read_their_coordinates() {
        let f = Formula::parse("2*x + y^2 + sin(PI*x)", 2).unwrap();
        let value = f.eval(&[0.5, 3.0]);
        assert!((value - (1.0 + 9.0 + 1.0)).abs() < 1e-12, "{value}");
        let g = Formula::parse("y - 1", 2).unwrap();
        assert_eq!(g.eval(&[7.0, 3.0]), 2.0);
        assert!(Formula::parse("y", 1)
            .unwrap_err()
            .contains("unknown variable `y`"));
        assert!(Formula::parse("sin(x", 1)
            .unwrap_err()
            .contains("not a formula"));
        assert_eq!(Formula::parse("3.5", 1).unwrap().eval(&[1.0]), 3.5);
        let sci = Formula::parse("2.5e11*x + 1E-3 - x2e", 1);
        assert!(sci.unwrap_err().contains("unknown variable `x2e`"));
        let sci = Formula::parse("2.5e11*x + 1E-3 + 4e+2", 1).unwrap();
        assert_eq!(sci.eval(&[2.0]), 5e11 + 1e-3 + 400.0);
    }
}
