//! The run's outcome: the matrix, its tables and reproducers written, a
//! summary, and the exit status.

use std::path::Path;
use std::process::ExitCode;

use glint::drivers::Verdict;
use glint::output::Outputs;
use glint::scene::Overrides;

use super::identify::Driver;
use super::staging::Staging;
use super::table::{self, Column, Matrix, Row};
use super::{probe, DriversArgs};
use crate::cli::console::{out, outln};

/// The matrix of `rows` over the tested `drivers`, with the `absent` ones
/// named beside it.
pub(super) fn matrix(
    drivers: &[Driver],
    absent: &[Driver],
    rows: Vec<Row>,
    size: &Overrides,
    seconds: f64,
) -> Matrix {
    Matrix {
        columns: drivers
            .iter()
            .map(|d| Column {
                icd: d.icd.clone(),
                name: d.name.clone(),
                identity: d.identity.as_ref().ok().cloned(),
                load: d.identity.as_ref().err().cloned(),
            })
            .collect(),
        absent: absent
            .iter()
            .map(|d| (d.icd.clone(), d.absence()))
            .collect(),
        rows,
        size: (size.width.unwrap_or(0), size.height.unwrap_or(0)),
        seconds,
        experiment: std::env::var("GLINT_EXPERIMENT").ok(),
        validation: probe::validation_layer(),
    }
}

/// Writes the reproducers (`staging` replaces `repro_root`) and the
/// tables, says what was written, and gives the exit status: 0 says every
/// cell ran and some image was held to its reference; a run of refusals,
/// errors or cells past the budget tested nothing, or not everything.
pub(super) fn finish(
    matrix: &Matrix,
    a: &DriversArgs,
    outputs: Outputs,
    staging: Staging,
    repro_root: &Path,
) -> anyhow::Result<ExitCode> {
    staging.replace(repro_root)?;
    table::write_all(matrix, &a.output, outputs)?;
    out!("{}", table::summary(matrix));
    let cells = || matrix.rows.iter().flat_map(|r| &r.cells);
    outln!(
        "wrote {}/index.html, drivers.md, drivers.csv, drivers.json{} in {:.1} s",
        glint::printable::path(&a.output),
        if cells().any(|c| c.repro.is_some()) {
            " and repro/"
        } else {
            ""
        },
        matrix.seconds
    );
    if matrix.failures() > 0 {
        return Ok(ExitCode::from(1));
    }
    let verdicts: Vec<&Verdict> = cells().map(|c| &c.verdict).collect();
    let not_run = verdicts
        .iter()
        .filter(|v| matches!(v, Verdict::NotRun { .. }))
        .count();
    anyhow::ensure!(
        not_run == 0,
        "{not_run} of {} cells were not run: the run reached its --budget of {} s (the tables say which)",
        verdicts.len(),
        a.budget.unwrap_or_default()
    );
    anyhow::ensure!(
        verdicts
            .iter()
            .any(|v| matches!(v, Verdict::Pass { .. } | Verdict::IllConditioned { .. })),
        "nothing was tested: every cell is refused or an error (the tables say why)"
    );
    Ok(ExitCode::SUCCESS)
}
