//! report.md, report.csv and report.json.

use std::fmt::Write;

use super::{Report, ROW_HEADERS};

fn opt(v: Option<f64>) -> String {
    v.map_or_else(String::new, |v| format!("{v:.6}"))
}

/// One row a measurement, quoted where a field needs it (a scene's name
/// may hold a comma or a quote); `reference` says what its error is
/// against: the scene's own CPU f64 render, or (the sampling axis) the
/// converged one.
pub fn csv(r: &Report) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let header = "scene,variant,backend,precision,intersect,max_depth,samples,width,height,median_s,upload_s,dispatch_s,readback_s,rays_per_s,compile_s,pipeline_s,max_abs,rmse,psnr_db,frac_over_1_255,nonfinite,flip_mean,pareto,reference";
    w.write_record(header.split(','))
        .expect("writing to memory");
    for s in &r.scenes {
        let tagged = s
            .measurements
            .iter()
            .map(|m| (m, "scene"))
            .chain(s.sampling.iter().map(|m| (m, "converged")));
        for (m, reference) in tagged {
            let e = &m.error;
            let record = [
                s.name.clone(),
                m.variant.name(),
                m.variant.backend().to_owned(),
                format!("{:?}", m.variant.precision()).to_lowercase(),
                m.variant
                    .intersect()
                    .map_or(String::new(), |i| format!("{i:?}").to_lowercase()),
                m.max_depth.to_string(),
                m.samples.to_string(),
                s.width.to_string(),
                s.height.to_string(),
                format!("{:.6}", m.time.median_s),
                opt(m.time.upload_s),
                opt(m.time.dispatch_s),
                opt(m.time.readback_s),
                format!("{:.0}", m.time.rays_per_s),
                opt(m.setup.map(|x| x.compile_s)),
                opt(m.setup.map(|x| x.pipeline_s)),
                format!("{:e}", e.max_abs),
                format!("{:e}", e.rmse),
                super::psnr(e.psnr_db, 2, ""),
                format!("{:e}", e.frac_over_1_255),
                e.nonfinite.to_string(),
                format!("{:e}", m.flip_mean),
                m.pareto.to_string(),
                reference.to_owned(),
            ];
            w.write_record(&record).expect("writing to memory");
        }
    }
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("UTF-8 fields")
}

/// report.json: the whole report.
pub fn json(r: &Report) -> String {
    serde_json::to_string_pretty(r).expect("a report serializes")
}

/// report.md: a table a scene.
pub fn markdown(r: &Report) -> String {
    let mut out = String::from("# glint report: error against run time\n\n");
    let _ = writeln!(
        out,
        "- machine: {} ({} threads), {}",
        r.machine.cpu, r.machine.threads, r.machine.os
    );
    let _ = writeln!(
        out,
        "- Vulkan device: {} ({}), driver {}, Vulkan {}",
        r.device.name, r.device.kind, r.device.driver, r.device.api_version
    );
    let _ = writeln!(out, "- times: median of {} warm runs; GPU times are upload + dispatch + readback, apart from the one-time device ({:.3} s), shader compile and pipeline costs", r.runs, r.device_s);
    let _ = writeln!(out, "- errors: against the CPU f64 reference at the scene's own settings; FLIP is the mean LDR-FLIP of the sRGB 8-bit images; * marks the scene's Pareto front (no variant both faster and more accurate)\n");
    for s in &r.scenes {
        let _ = writeln!(
            out,
            "## {} ({}x{}, {}, depth {})\n",
            s.name, s.width, s.height, s.sampling_summary, s.max_depth
        );
        let _ = writeln!(out, "| {} |", ROW_HEADERS.join(" | "));
        let _ = writeln!(out, "|{}", "---|".repeat(ROW_HEADERS.len()));
        rows(&mut out, &s.measurements);
        if !s.sampling.is_empty() {
            let _ = writeln!(
                out,
                "\n### {}: the sampling axis, against CPU f64 at {n}x{n} uniform samples\n",
                s.name,
                n = super::CONVERGED_SAMPLES
            );
            let _ = writeln!(out, "| {} |", ROW_HEADERS.join(" | "));
            let _ = writeln!(out, "|{}", "---|".repeat(ROW_HEADERS.len()));
            rows(&mut out, &s.sampling);
        }
        out.push('\n');
    }
    out
}

/// One table row a measurement, the Pareto front starred.
fn rows(out: &mut String, ms: &[super::Measurement]) {
    for m in ms {
        let mut cells = m.row();
        if m.pareto {
            cells[0].push_str(" *");
        }
        let _ = writeln!(out, "| {} |", cells.join(" | "));
    }
}
