//! The stability sweep's files: `stability.csv`, `stability.json` and the bar chart.
use super::StabilityRow;

/// Write `stability.csv`, `stability.json` and `stability.png` (critical Courant number of
/// every configuration: empirical and von Neumann) into `dir`.
pub fn write(dir: &std::path::Path, rows: &[StabilityRow]) -> anyhow::Result<()> {
    let csv_path = dir.join("stability.csv");
    impact_io::write_atomic(&csv_path, |w| {
        writeln!(
            w,
            "dim,method,points_per_cell,integrator,flux,update,layout,empirical,von_neumann,monotone"
        )?;
        for r in rows {
            writeln!(
                w,
                "{},{},{},{},{},{},{},{:.6},{},{}",
                r.dim,
                r.method,
                r.points_per_cell,
                r.integrator,
                r.flux,
                r.update,
                r.layout,
                r.empirical,
                r.von_neumann.map_or(String::new(), |v| format!("{v:.6}")),
                r.monotone.map_or(String::new(), |v| format!("{v:.6}"))
            )?;
        }
        Ok(())
    })?;
    impact_io::write_json(&dir.join("stability.json"), &rows)?;
    chart(&dir.join("stability.png"), rows)?;
    Ok(())
}

/// The critical Courant number of every configuration as grouped bars (empirical, von
/// Neumann, monotonicity), one category per configuration, into `path` (PNG or SVG).
pub fn chart(path: &std::path::Path, rows: &[StabilityRow]) -> anyhow::Result<()> {
    impact_io::plot::save(path, &figure(rows))?;
    Ok(())
}

/// The bar figure of [`chart`]. A limit of zero has no bar and says `0` at its place; a
/// limit not computed for that configuration (von Neumann and monotonicity: DGMPM only)
/// says `n/c`, so the two never look alike.
pub fn figure(rows: &[StabilityRow]) -> impact_io::plot::BarFigure {
    use impact_io::plot::{BarFigure, BarGroup};
    let columns: [(&str, Vec<Option<f64>>); 3] = [
        (
            "empirical",
            rows.iter().map(|r| Some(r.empirical)).collect(),
        ),
        ("von Neumann", rows.iter().map(|r| r.von_neumann).collect()),
        ("monotone up to", rows.iter().map(|r| r.monotone).collect()),
    ];
    let mark = |v: &Option<f64>| match v {
        None => Some("n/c".to_string()),
        Some(x) if *x <= 0.0 => Some("0".to_string()),
        Some(_) => None,
    };
    BarFigure {
        title: "critical Courant number per configuration".into(),
        axis: "critical Courant number c·Δt/Δx".into(),
        categories: rows.iter().map(StabilityRow::label).collect(),
        missing: columns
            .iter()
            .map(|(_, values)| values.iter().map(mark).collect())
            .collect(),
        groups: columns
            .into_iter()
            .map(|(label, values)| BarGroup {
                label: label.into(),
                values: values.into_iter().map(|v| v.filter(|x| *x > 0.0)).collect(),
            })
            .collect(),
        note: Some(
            "0: the limit is zero (no Courant number is stable, or monotone). n/c: not \
             computed for this configuration (von Neumann and monotonicity: DGMPM only)."
                .into(),
        ),
        width: impact_io::plot::PrintWidth::Full,
    }
}
