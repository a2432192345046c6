//! Method options, typed end to end: each option is one enum whose names are spelled once
//! (in `option_enum!`) and serve the scene parser (serde), the command line
//! (`clap::ValueEnum`, behind the `clap` feature), tables, file names and the flags the
//! work-precision ladder passes on ([`MethodConfig::to_flags`]).
//!
//! [`MethodConfig`] holds what every method shares (Courant number, points per cell) and
//! the options of one method ([`MethodOptions`]). A new option is a new enum here and a
//! field of its method's options struct; nothing else spells its names.
use serde::{Deserialize, Serialize};

pub use crate::scheme_order::SchemeOrder;

mod config;
pub use config::{DgmpmOptions, FemOptions, MethodConfig, MethodOptions, MpmOptions};

/// An option enum: the variants with their names, `name()`, `parse()`, `ALL`, `NAMES`,
/// serde (by name; an unknown name is rejected with the list of allowed names), `Display`
/// and, behind the `clap` feature, `clap::ValueEnum`.
macro_rules! option_enum {
    ($(#[$meta:meta])* $name:ident {
        $($(#[$vmeta:meta])* $variant:ident = $text:literal),+ $(,)?
    }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $($(#[$vmeta])* $variant),+
        }

        impl $name {
            /// Every variant, in declaration order.
            pub const ALL: [Self; [$(stringify!($variant)),+].len()] = [$(Self::$variant),+];
            /// Every name, in declaration order.
            pub const NAMES: &'static [&'static str] = &[$($text),+];
            /// The name used in scene files, flags, tables and file names.
            pub fn name(self) -> &'static str {
                match self {
                    $(Self::$variant => $text),+
                }
            }
            /// The variant of a name.
            pub fn parse(text: &str) -> Option<Self> {
                Self::ALL.iter().copied().find(|v| v.name() == text)
            }
            /// The allowed names, quoted, as a list ending in "or" (for error messages).
            pub fn allowed() -> String {
                let quoted: Vec<String> = Self::NAMES.iter().map(|n| format!("\"{n}\"")).collect();
                match quoted.split_last() {
                    Some((last, rest)) if !rest.is_empty() => {
                        format!("{} or {last}", rest.join(", "))
                    }
                    _ => quoted.concat(),
                }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name())
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
                let text = String::deserialize(d)?;
                Self::parse(&text).ok_or_else(|| {
                    serde::de::Error::custom(format!(
                        "unknown value {text:?} (allowed: {})",
                        Self::allowed()
                    ))
                })
            }
        }

        #[cfg(feature = "clap")]
        impl clap::ValueEnum for $name {
            fn value_variants<'a>() -> &'a [Self] {
                &Self::ALL
            }
            fn to_possible_value(&self) -> Option<clap::builder::PossibleValue> {
                Some(clap::builder::PossibleValue::new(self.name()))
            }
        }
    };
}
pub(crate) use option_enum;

option_enum! {
    /// Which method a configuration belongs to.
    MethodKind {
        /// Discontinuous Galerkin material point method.
        Dgmpm = "dgmpm",
        /// Material point method.
        Mpm = "mpm",
        /// Explicit finite elements.
        Fem = "fem",
    }
}

option_enum! {
    /// Time integrator of DGMPM's semi-discrete system (paper §3.2).
    Integrator {
        /// Forward Euler.
        Euler = "euler",
        /// Two-stage Runge-Kutta (Heun / SSP-RK2).
        Rk2 = "rk2",
    }
}

option_enum! {
    /// How DGMPM points are updated after the nodal solve (the paper leaves it open).
    PointUpdate {
        /// `q_α = Σ_i S_iα q_i^{n+1}`: points take the interpolated new nodal field (default).
        Nodal = "nodal",
        /// `q_α += Σ_i S_iα (q_i^{n+1} - q_i^n)`: points add the interpolated increment.
        Increment = "increment",
    }
}

option_enum! {
    /// DGMPM's treatment of waves crossing cells obliquely in 2D (LeVeque 2002, ch. 20-21).
    TransverseFlux {
        /// Donor-cell upwind: normal Godunov fluxes only.
        DonorCell = "dcu",
        /// Corner transport upwind: the normal fluctuations are split by the transverse
        /// Riemann solver and correct the transverse fluxes.
        Ctu = "ctu",
    }
}

option_enum! {
    /// DGMPM's Riemann solver for Saint-Venant–Kirchhoff (linear elasticity always uses the
    /// exact linear solver).
    RiemannSolver {
        /// Linearised (acoustic) solver with each side's impedance `ρ₀ c(F)` (Toro 2009, §9.3).
        Approximate = "approximate",
        /// Exact solver: shock and rarefaction curves, Newton on the star stress (1D).
        Exact = "exact",
        /// J2: the linear-elastic solver, then the return map at the points (default).
        Elastic = "elastic",
        /// J2 rod: the exact elastoplastic face solver (elastic precursor up to yield, then
        /// the plastic wave); 1D, one point per cell.
        Elastoplastic = "elastoplastic",
    }
}

option_enum! {
    /// The wave limiter `φ(θ)` of DGMPM's second-order corrections (`order = 2`; LeVeque
    /// 2002, §6.9 and §6.12; Clawpack's `limiter.f`), `θ` the upwind neighbour face's wave
    /// of the same family projected on the face's own.
    WaveLimiter {
        /// `φ = 1`: unlimited, the Lax-Wendroff scheme (not TVD).
        None = "none",
        /// `φ = max(0, min(1, θ))`.
        Minmod = "minmod",
        /// `φ = max(0, min(1, 2θ), min(2, θ))` (Roe).
        Superbee = "superbee",
        /// `φ = (θ + |θ|)/(1 + |θ|)`.
        VanLeer = "vanleer",
        /// Monotonized centred: `φ = max(0, min((1 + θ)/2, 2, 2θ))` (van Leer 1977).
        Mc = "mc",
    }
}

option_enum! {
    /// MPM stress update order.
    StressUpdate {
        /// Update stress last, from the grid-updated nodal velocity `v_i + Δt f_i/m_i`.
        Usl = "usl",
        /// Update stress last, from the nodal velocity mapped again from the updated point
        /// velocities (the remap of Sulsky, Zhou & Schreyer 1995; "MUSL").
        Musl = "musl",
        /// Update stress first, from the nodal velocity mapped at the start of the step.
        Usf = "usf",
    }
}

option_enum! {
    /// Frame in which MPM evaluates its shape functions.
    MpmFrame {
        /// Shape functions at the points' reference positions, reference volumes: the grid is
        /// the reference configuration (the paper's "total Lagrangian formulation", §5.3).
        TotalLagrangian = "total-lagrangian",
        /// Shape functions at the current positions, volumes updated: points move through the
        /// grid (Sulsky, Zhou & Schreyer 1995).
        UpdatedLagrangian = "updated-lagrangian",
    }
}

option_enum! {
    /// MPM shape functions (weights of a point on the background grid's nodes).
    MpmShape {
        /// Linear (1D) / multilinear hat functions: 2 nodes per axis (Sulsky et al. 1994).
        Linear = "linear",
        /// Uniform GIMP: the hat convolved with the point's domain of half a point spacing
        /// (Bardenhagen & Kober 2004): 3 nodes per axis, C¹ across cell faces.
        Gimp = "gimp",
        /// Quadratic B-spline on the padded grid (Steffen, Kirby & Berzins 2008): 3 nodes per
        /// axis, C¹.
        Bspline2 = "bspline2",
        /// Cubic B-spline on the padded grid: 4 nodes per axis, C².
        Bspline3 = "bspline3",
        /// CPDI1 (Sadeghirad, Brannon & Burghardt 2011): the hat averaged over the point's
        /// parallelogram domain, whose edge vectors follow `F`; in 1D the segment `x ± r`.
        /// 4 nodes per axis.
        Cpdi = "cpdi",
    }
}

option_enum! {
    /// MPM velocity transfer from the grid to the points (and, for APIC, back):
    /// `impact_mpm`'s `transfer` module states the formulas and references.
    MpmTransfer {
        /// FLIP: `v_p += Σ_i w_ip Δv_i`, the interpolated nodal velocity increment (Brackbill
        /// & Ruppel 1986; Sulsky, Zhou & Schreyer 1995).
        Flip = "flip",
        /// PIC: `v_p = Σ_i w_ip v_i`, the interpolated new nodal velocity (Harlow 1964).
        Pic = "pic",
        /// `v_p = α (v_p + Σ_i w_ip Δv_i) + (1 − α) Σ_i w_ip v_i`, the FLIP share `α` given
        /// by `flip_fraction`.
        Blend = "blend",
        /// APIC (Jiang, Schroeder, Selle, Teran & Stomakhin 2015): PIC plus a per-point
        /// affine velocity `C_p`, carried to the grid as `v_p + C_p (x_i − x_p)`.
        Apic = "apic",
    }
}

option_enum! {
    /// Direction of a pressure load.
    LoadDirection {
        /// Pushing into the body (positive pressure).
        Compression = "compression",
        /// Pulling (negative pressure).
        Tension = "tension",
    }
}

option_enum! {
    /// Constitutive model of a scene (`material.model`).
    MaterialModel {
        /// Small-strain linear elasticity: Cauchy stress, points fixed in the reference grid.
        LinearElastic = "linear-elastic",
        /// Saint-Venant–Kirchhoff, total Lagrangian (large strain; paper §5.3).
        Svk = "svk",
        /// Small-strain J2 plasticity with linear isotropic hardening (`crate::plasticity`):
        /// uniaxial stress in 1D, plane strain in 2D.
        J2 = "j2",
    }
}

option_enum! {
    /// Condition on one edge of the body (`boundary.<edge>.kind`).
    EdgeKind {
        /// Traction-free.
        Free = "free",
        /// Normal pressure `value` (Pa, positive in compression) on the segment.
        Pressure = "pressure",
        /// An impactor bonded to the body: velocity `value` (m/s) into the body, zero
        /// tangential velocity (no slip), on the segment.
        Velocity = "velocity",
        /// A frictionless impactor: normal velocity `value` (m/s) into the body, zero shear
        /// traction, on the segment.
        NormalVelocity = "normal-velocity",
        /// Zero normal velocity and zero shear traction (a mirror plane).
        Symmetry = "symmetry",
    }
}

option_enum! {
    /// Time history of a boundary load (`crate::load`): `g(t)` multiplies the edge's value.
    LoadShape {
        /// `g = 1` from `t = 0` on (the paper's loads).
        Step = "step",
        /// Linear rise over `duration`, then constant.
        Ramp = "ramp",
        /// Quintic smoothstep rise over `duration` (C²), then constant.
        SmoothRamp = "smooth-ramp",
        /// `sin(2π t/duration)`.
        Sine = "sine",
        /// 1 for `t < duration`, then 0.
        Pulse = "pulse",
    }
}

option_enum! {
    /// Where the points of a cell sit (`crate::points::PointLayout`).
    LayoutKind {
        /// At the sub-cell centres.
        Centred = "centred",
        /// Every point shifted by `shift` sub-cell widths along each axis.
        Shifted = "shifted",
        /// At the given local `positions`.
        Given = "given",
    }
}

option_enum! {
    /// Which cells, faces or nodes a loaded segment acts on where its end cuts one.
    SegmentCover {
        /// All or nothing, by the centre of the face (DGMPM), of the point's face (MPM)
        /// or by the node's position (FEM): Clawpack's and the paper's rule.
        Centre = "centre",
        /// In proportion to the covered fraction of the face or tributary length: the
        /// load's resultant then equals value × segment length on any grid.
        Fraction = "fraction",
    }
}

option_enum! {
    /// How DGMPM's CTU treats the edges (2D).
    EdgeTreatment {
        /// Ghost cells, and the CTU corrections on edge faces restricted to what the edge's
        /// condition leaves free (free edges stay exactly traction-free); no diagonal
        /// ghost at a corner of two traction edges (default).
        Restricted = "restricted",
        /// Ghost cells only, as Clawpack: the corrections on edge faces are not restricted
        /// and a traction corner's diagonal ghost is the ghost of the ghost cell.
        Ghost = "ghost",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_list_the_allowed_ones() {
        for v in TransverseFlux::ALL {
            assert_eq!(TransverseFlux::parse(v.name()), Some(v));
        }
        #[derive(Deserialize)]
        struct S {
            #[allow(dead_code)]
            frame: MpmFrame,
        }
        let e = toml::from_str::<S>("frame = \"eulerian\"")
            .err()
            .expect("an unknown name is refused")
            .to_string();
        assert!(
            e.contains("eulerian")
                && e.contains("total-lagrangian")
                && e.contains("updated-lagrangian"),
            "{e}"
        );
    }
}
