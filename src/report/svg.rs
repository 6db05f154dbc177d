//! error_vs_time.svg: every measurement as a point, rmse against median time,
//! both on log scales; each scene's Pareto front as a dashed line.

use std::fmt::Write;

use super::{escape, Measurement, Report, Variant};
use crate::gpu::Intersect;

const W: f64 = 900.0;
const H: f64 = 600.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 230.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 60.0;
/// Where an error of exactly zero (the reference itself) is drawn.
const ZERO_ERROR: f64 = 1e-9;

/// The colour of a variant's family.
fn colour(v: Variant) -> &'static str {
    match v {
        Variant::Gpu(Intersect::Robust) => "#1f77b4",
        Variant::Gpu(Intersect::Naive) => "#d62728",
        Variant::GpuGeneric => "#8c564b",
        Variant::Gpu64 => "#9467bd",
        Variant::Cpu32 => "#2ca02c",
        Variant::Cpu64 => "#111111",
        Variant::GpuDepth(_) => "#7fb8e6",
        Variant::GpuSamples(_) => "#ff9f3f",
        Variant::GpuUniform(_) => "#17becf",
        Variant::GpuAdaptive(..) => "#e377c2",
        Variant::GpuContrast(..) => "#bcbd22",
        Variant::GpuRange(..) => "#393b79",
    }
}

/// The legend: one variant of each family, and its label.
const FAMILIES: [(Variant, &str); 12] = [
    (Variant::Gpu(Intersect::Robust), "gpu f32 robust"),
    (Variant::Gpu(Intersect::Naive), "gpu f32 naive"),
    (Variant::GpuGeneric, "gpu f32 generic shader"),
    (Variant::Gpu64, "gpu f64"),
    (Variant::Cpu32, "cpu f32"),
    (Variant::Cpu64, "cpu f64 (reference)"),
    (Variant::GpuDepth(1), "gpu f32, lower depth"),
    (Variant::GpuSamples(1), "gpu f32, fewer samples"),
    (Variant::GpuUniform(1), "gpu f32, uniform sampling"),
    (Variant::GpuAdaptive(0, 1), "gpu f32, adaptive sampling"),
    (Variant::GpuContrast(0, 4), "gpu f32, contrast sampling"),
    (
        Variant::GpuRange(0, 4),
        "gpu f32, contrast sampling, range test",
    ),
];

/// The marker shapes, one a scene: a circle, a square, a diamond, a
/// triangle up, a triangle down and a cross; past six scenes the same
/// shapes come again hollow, so that twelve scenes are told apart.
const SHAPES: usize = 6;

/// Scene `shape`'s marker at (x, y), filled with `fill`, its tooltip `title`.
fn marker(shape: usize, x: f64, y: f64, fill: &str, title: &str) -> String {
    let r = 5.5;
    let points = |corners: &[(f64, f64)]| {
        let list: Vec<String> = corners
            .iter()
            .map(|(dx, dy)| format!("{:.1},{:.1}", x + dx * r, y + dy * r))
            .collect();
        format!("<polygon points=\"{}\"", list.join(" "))
    };
    let (body, tag) = match shape % SHAPES {
        0 => (
            format!("<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"{r}\""),
            "circle",
        ),
        1 => (
            points(&[(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]),
            "polygon",
        ),
        2 => (
            points(&[(0.0, -1.3), (1.3, 0.0), (0.0, 1.3), (-1.3, 0.0)]),
            "polygon",
        ),
        3 => (points(&[(0.0, -1.3), (1.2, 1.0), (-1.2, 1.0)]), "polygon"),
        4 => (points(&[(0.0, 1.3), (1.2, -1.0), (-1.2, -1.0)]), "polygon"),
        _ => (
            points(&[
                (-0.4, -1.2),
                (0.4, -1.2),
                (0.4, -0.4),
                (1.2, -0.4),
                (1.2, 0.4),
                (0.4, 0.4),
                (0.4, 1.2),
                (-0.4, 1.2),
                (-0.4, 0.4),
                (-1.2, 0.4),
                (-1.2, -0.4),
                (-0.4, -0.4),
            ]),
            "polygon",
        ),
    };
    let paint = if shape / SHAPES % 2 == 0 {
        format!("fill=\"{fill}\" fill-opacity=\"0.85\" stroke=\"#fff\" stroke-width=\"1\"")
    } else {
        format!("fill=\"#fff\" fill-opacity=\"0.85\" stroke=\"{fill}\" stroke-width=\"2\"")
    };
    format!("{body} {paint}><title>{title}</title></{tag}>\n")
}

/// The plot of every measurement's error (rmse) against its time, on log
/// axes: a colour a variant's family, a marker shape a scene.
pub fn plot(r: &Report) -> String {
    plot_of(
        r,
        |s| &s.measurements,
        "Every variant: error against run time",
        "RMSE against CPU f64",
    )
}

/// The sampling axis's plot (sampling_vs_time.svg): each scene's uniform
/// and adaptive sampling against its converged render.
pub fn plot_sampling(r: &Report) -> String {
    plot_of(
        r,
        |s| &s.sampling,
        "Uniform, adaptive and contrast sampling: error against run time",
        "RMSE against CPU f64 at 16x16 samples",
    )
}

fn plot_of(
    r: &Report,
    pick: impl Fn(&super::SceneReport) -> &[Measurement],
    title: &str,
    against: &str,
) -> String {
    let points: Vec<(usize, &Measurement)> = r
        .scenes
        .iter()
        .enumerate()
        .flat_map(|(i, s)| pick(s).iter().map(move |m| (i, m)))
        .collect();
    let err = |m: &Measurement| m.error.rmse.max(ZERO_ERROR);
    let (mut tmin, mut tmax, mut emin, mut emax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (_, m) in &points {
        tmin = tmin.min(m.time.median_s);
        tmax = tmax.max(m.time.median_s);
        emin = emin.min(err(m));
        emax = emax.max(err(m));
    }
    if points.is_empty() {
        (tmin, tmax, emin, emax) = (1e-3, 1.0, ZERO_ERROR, 1.0);
    }
    let (lt0, lt1) = (
        tmin.log10().floor(),
        tmax.log10().ceil().max(tmin.log10().floor() + 1.0),
    );
    let (le0, le1) = (
        emin.log10().floor(),
        emax.log10().ceil().max(emin.log10().floor() + 1.0),
    );
    let x = |t: f64| LEFT + (t.log10() - lt0) / (lt1 - lt0) * (W - LEFT - RIGHT);
    let y = |e: f64| H - BOTTOM - (e.log10() - le0) / (le1 - le0) * (H - TOP - BOTTOM);

    let mut s = String::new();
    let _ = writeln!(s, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{W}\" height=\"{H}\" viewBox=\"0 0 {W} {H}\" font-family=\"sans-serif\" font-size=\"12\">");
    let _ = writeln!(s, "<rect width=\"{W}\" height=\"{H}\" fill=\"#fff\"/>");
    let _ = writeln!(
        s,
        "<text x=\"{LEFT}\" y=\"22\" font-size=\"15\">{title} ({}; {})</text>",
        escape(&r.device.name),
        escape(&r.machine.cpu)
    );
    for d in lt0 as i32..=lt1 as i32 {
        let px = x(10f64.powi(d));
        let _ = writeln!(s, "<line x1=\"{px:.1}\" y1=\"{TOP}\" x2=\"{px:.1}\" y2=\"{:.1}\" stroke=\"#ddd\"/><text x=\"{px:.1}\" y=\"{:.1}\" text-anchor=\"middle\">1e{d}</text>", H - BOTTOM, H - BOTTOM + 18.0);
    }
    for d in le0 as i32..=le1 as i32 {
        let py = y(10f64.powi(d));
        let label = if 10f64.powi(d) <= ZERO_ERROR {
            "0".to_owned()
        } else {
            format!("1e{d}")
        };
        let _ = writeln!(s, "<line x1=\"{LEFT}\" y1=\"{py:.1}\" x2=\"{:.1}\" y2=\"{py:.1}\" stroke=\"#ddd\"/><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{label}</text>", W - RIGHT, LEFT - 6.0, py + 4.0);
    }
    let _ = writeln!(s, "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">median render time (s), log scale</text>", (LEFT + W - RIGHT) / 2.0, H - 18.0);
    let _ = writeln!(s, "<text transform=\"translate(22 {:.1}) rotate(-90)\" text-anchor=\"middle\">{against}, log scale (bottom row: exactly 0)</text>", (TOP + H - BOTTOM) / 2.0);
    // The plot area: nothing drawn in it may cross the axes.
    let _ = writeln!(s, "<clipPath id=\"plot-area\"><rect x=\"{LEFT}\" y=\"{TOP}\" width=\"{:.1}\" height=\"{:.1}\"/></clipPath>", W - LEFT - RIGHT, H - TOP - BOTTOM);
    // Pareto fronts first, under the points: each scene's among the
    // measurements this plot shows (the sampling axis has fronts of its own).
    for scene in &r.scenes {
        let mut front: Vec<&Measurement> = pick(scene).iter().filter(|m| m.pareto).collect();
        front.sort_by(|a, b| a.time.median_s.total_cmp(&b.time.median_s));
        let path: Vec<String> = front
            .iter()
            .map(|m| format!("{:.1},{:.1}", x(m.time.median_s), y(err(m))))
            .collect();
        if path.len() > 1 {
            let _ = writeln!(s, "<polyline points=\"{}\" clip-path=\"url(#plot-area)\" fill=\"none\" stroke=\"#888\" stroke-dasharray=\"5 4\" stroke-width=\"1.5\"><title>Pareto front of {}</title></polyline>", path.join(" "), escape(&scene.name));
        }
    }
    for (i, m) in &points {
        let scene = &r.scenes[*i];
        let title = format!(
            "{} / {}: {:.4} s, rmse {:.2e}{}",
            scene.name,
            m.variant.name(),
            m.time.median_s,
            m.error.rmse,
            if m.pareto { " (Pareto front)" } else { "" }
        );
        s.push_str(&marker(
            *i,
            x(m.time.median_s),
            y(err(m)),
            colour(m.variant),
            &escape(&title),
        ));
        if m.pareto {
            let _ = writeln!(s, "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"9\" fill=\"none\" stroke=\"#444\" stroke-width=\"1\"/>", x(m.time.median_s), y(err(m)));
        }
    }
    // Legend: colours for variants, shapes for scenes.
    let lx = W - RIGHT + 20.0;
    let mut ly = TOP + 10.0;
    // The families the plot shows.
    let shown = FAMILIES
        .into_iter()
        .filter(|(v, _)| points.iter().any(|(_, m)| colour(m.variant) == colour(*v)));
    for (variant, name) in shown {
        let c = colour(variant);
        let _ = writeln!(s, "<rect x=\"{lx}\" y=\"{:.1}\" width=\"12\" height=\"12\" fill=\"{c}\"/><text x=\"{:.1}\" y=\"{:.1}\">{name}</text>", ly - 10.0, lx + 18.0, ly);
        ly += 20.0;
    }
    ly += 10.0;
    for (i, scene) in r.scenes.iter().enumerate() {
        s.push_str(&marker(i, lx + 6.0, ly - 4.0, "#666", &escape(&scene.name)));
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{ly:.1}\">{}</text>",
            lx + 18.0,
            escape(&scene.name)
        );
        ly += 20.0;
    }
    let _ = writeln!(s, "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"9\" fill=\"none\" stroke=\"#444\"/><text x=\"{:.1}\" y=\"{:.1}\">Pareto front (dashed)</text>", lx + 6.0, ly + 6.0, lx + 18.0, ly + 10.0);
    s.push_str("</svg>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Five scenes shared four shapes (seed-fig3 and
    /// whitted-1980 were both circles); twelve are now told apart.
    #[test]
    fn twelve_scenes_have_twelve_markers() {
        let shapes: std::collections::HashSet<String> = (0..12)
            .map(|i| marker(i, 10.0, 10.0, "#123456", "t"))
            .collect();
        assert_eq!(shapes.len(), 12);
    }
}
