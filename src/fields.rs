//! The fields of a run kept in memory at every output time, for the Python package
//! (`crates/impact-py`): the samples' positions, velocity and stress, the plastic strain
//! where the model has one, the reference's averages over each sample's region, the
//! profile along the measuring line exactly as its CSV file holds it, and the σ_xx cell
//! map of 2D and 3D runs. [`crate::run::run_study_keeping`] fills them; `impact run`
//! keeps none.
use impact_core::method::Samples;
use impact_core::reference::Reference;
use impact_core::Vector;

/// One output time of one method. Arrays are flat and row-major: `n` samples, `dim`
/// components per vector, `dim × dim` per tensor.
#[derive(Debug, Clone, Default)]
pub struct Frame {
    /// Index of the output time (`<method>_t<index>.csv`).
    pub index: usize,
    /// Time (s).
    pub t: f64,
    /// Dimension.
    pub dim: usize,
    /// Reference (material) position `X` of each sample (m), `n × dim`.
    pub reference: Vec<f64>,
    /// Current position `x` of each sample (m), `n × dim`.
    pub position: Vec<f64>,
    /// Half-size of each sample's region in the reference configuration (m), `n × dim`.
    pub half_size: Vec<f64>,
    /// Velocity (m/s), `n × dim`.
    pub velocity: Vec<f64>,
    /// Stress (Pa), `n × dim × dim`: Cauchy `σ` in small strain, first Piola–Kirchhoff
    /// `Π` under Saint-Venant–Kirchhoff (see [`MethodFields::stress_name`]).
    pub stress: Vec<f64>,
    /// Out-of-plane stress `σ_zz` where the model sets it apart from plane strain (J2 in
    /// 2D, Pa); empty otherwise.
    pub stress_zz: Vec<f64>,
    /// Accumulated equivalent plastic strain (J2, dimensionless); empty otherwise.
    pub plastic_strain: Vec<f64>,
    /// The reference's averages of σ_xx (Pa) and v_x (m/s) over each sample's region; empty
    /// without a reference.
    pub reference_stress_xx: Vec<f64>,
    /// See [`Self::reference_stress_xx`].
    pub reference_velocity_x: Vec<f64>,
    /// The profile along the measuring line: the CSV file's header and columns.
    pub profile: (Vec<String>, Vec<Vec<f64>>),
    /// σ_xx per cell of the map's plane (Pa, `NaN` where no sample lies; 2D and 3D).
    pub map: Vec<f64>,
}

impl Frame {
    /// The frame of `samples` at output `index`, time `t`, with the profile's header and
    /// columns and the reference's averages over each sample's region.
    pub fn of<const D: usize>(
        samples: &Samples<D>,
        (index, t): (usize, f64),
        (header, columns): (&[String], &[Vec<f64>]),
        reference: Option<&Reference>,
    ) -> Self {
        let vectors = |v: &[Vector<D>]| v.iter().flat_map(|x| x.iter().copied()).collect();
        let stress = samples
            .stress
            .iter()
            .flat_map(|s| (0..D * D).map(move |k| s[(k / D, k % D)]))
            .collect();
        let exact: Vec<(f64, f64)> = reference.map_or_else(Vec::new, |r| {
            samples
                .reference
                .iter()
                .zip(&samples.half_size)
                .map(|(c, h)| r.averages(&(c - h), &(c + h), t))
                .collect()
        });
        Self {
            index,
            t,
            dim: D,
            reference: vectors(&samples.reference),
            position: vectors(&samples.position),
            half_size: vectors(&samples.half_size),
            velocity: vectors(&samples.velocity),
            stress,
            stress_zz: samples.stress_zz.clone(),
            plastic_strain: samples.plastic_strain.clone(),
            reference_stress_xx: exact.iter().map(|e| e.0).collect(),
            reference_velocity_x: exact.iter().map(|e| e.1).collect(),
            profile: (header.to_vec(), columns.to_vec()),
            map: Vec::new(),
        }
    }
}

/// Every output time of one method's run.
#[derive(Debug, Clone, Default)]
pub struct MethodFields {
    /// Method name (`dgmpm`, `mpm`, `fem`).
    pub method: String,
    /// Name of the stress the samples carry (`cauchy_stress` or `piola_stress`).
    pub stress_name: String,
    /// One frame per output time reached.
    pub frames: Vec<Frame>,
}
