//! The reports' figures (learning curves with standard-error bands, labelled points, distribution
//! functions), drawn with plotters to SVG and PNG. The PNG's text
//! uses DejaVu Sans compiled in, so the plots need no system fonts.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Once;

/// One model's curve: the mean across runs and its standard error, per episode.
pub struct Series {
    /// The legend's name.
    pub label: String,
    /// The mean across runs, per episode.
    pub mean: Vec<f64>,
    /// Its standard error, per episode.
    pub se: Vec<f64>,
}

const SIZE: (u32, u32) = (900, 520);

/// Colour-blind-safe (Okabe-Ito).
const COLOURS: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(120, 120, 120),
    RGBColor(0, 0, 0),
];

/// Registers the bundled DejaVu Sans as "sans-serif": plotters has no font of its own, and the
/// machine's fonts are not searched (no `ttf` feature), so every chart needs this first.
pub fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
            .unwrap_or_else(|_| panic!("the bundled DejaVu Sans is a valid font"));
    });
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    ylabel: &str,
    series: &[Series],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let len = series.iter().map(|s| s.mean.len()).max().unwrap_or(1).max(2);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for (m, e) in s.mean.iter().zip(&s.se) {
            lo = lo.min(m - e);
            hi = hi.max(m + e);
        }
    }
    if !lo.is_finite() || !hi.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-3);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0f64..len as f64, (lo - pad)..(hi + pad))
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("episode")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_desc(ylabel)
        .label_style(("sans-serif", 14))
        // No minor grid: it made every PNG half a megabyte.
        .max_light_lines(0)
        .draw()
        .map_err(err)?;
    for (i, s) in series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let upper = s.mean.iter().zip(&s.se).enumerate().map(|(x, (m, e))| (x as f64, m + e));
        let lower = s.mean.iter().zip(&s.se).enumerate().rev().map(|(x, (m, e))| (x as f64, m - e));
        chart
            .draw_series(std::iter::once(Polygon::new(upper.chain(lower).collect::<Vec<_>>(), colour.mix(0.2))))
            .map_err(err)?;
        line(&mut chart, s.mean.iter().enumerate().map(|(x, &m)| (x as f64, m)), colour, &s.label)?;
    }
    legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    root.present().map_err(err)
}

/// A chart over two f64 axes.
type Plane<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A labelled line, entered in the legend.
fn line<'a, DB: DrawingBackend + 'a>(
    chart: &mut Plane<'a, DB>,
    points: impl IntoIterator<Item = (f64, f64)>,
    colour: RGBColor,
    label: &str,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    chart
        .draw_series(LineSeries::new(points, colour.stroke_width(2)))
        .map_err(|e| e.to_string())?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
    Ok(())
}

/// The legend of the labelled lines, in one style for every figure.
fn legend<'a, DB: DrawingBackend + 'a>(chart: &mut Plane<'a, DB>, position: SeriesLabelPosition) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(position)
        .draw()
        .map_err(|e| e.to_string())
}

/// Draws a chart on any plotters backend (the SVG and the PNG of one figure).
trait Chart {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static;
}

/// `<stem>.<ext>`. Not `Path::with_extension`, which would cut a stem with a dot in it
/// (`untrained-x0.5-reward` became `untrained-x0.svg`, and the entropy figure overwrote the reward's).
fn file(stem: &Path, ext: &str) -> PathBuf {
    let mut name = stem.as_os_str().to_owned();
    name.push(".");
    name.push(ext);
    name.into()
}

/// Writes `<stem>.svg` and `<stem>.png` of `chart`.
fn write(stem: &Path, chart: &impl Chart) -> Result<(), String> {
    register_font();
    let svg = file(stem, "svg");
    chart.draw(SVGBackend::new(&svg, SIZE).into_drawing_area()).map_err(|e| format!("{}: {e}", svg.display()))?;
    let (png, mut rgb) = (file(stem, "png"), vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize]);
    chart
        .draw(BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area())
        .map_err(|e| format!("{}: {e}", png.display()))?;
    let rgba: Vec<u8> = rgb.chunks_exact(3).flat_map(|p| [p[0], p[1], p[2], 255]).collect();
    crate::write_png(&png, SIZE.0 as usize, SIZE.1 as usize, &rgba)
}

struct Curves<'a> {
    title: &'a str,
    ylabel: &'a str,
    series: &'a [Series],
}

impl Chart for Curves<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        draw(root, self.title, self.ylabel, self.series)
    }
}

/// Writes `<stem>.svg` and `<stem>.png`: per-episode curves with their standard-error bands.
pub fn curves(stem: &Path, title: &str, ylabel: &str, series: &[Series]) -> Result<(), String> {
    write(stem, &Curves { title, ylabel, series })
}

fn draw_scatter<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    points: &[(String, f64, f64)],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let fold = |f: fn(&(String, f64, f64)) -> f64| {
        points.iter().map(f).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
    };
    let (xlo, xhi) = fold(|p| p.1);
    let (ylo, yhi) = fold(|p| p.2);
    let (ylo, yhi) = (ylo.min(1.0) - 0.1, yhi.max(1.0) + 0.1);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d((xlo / 1.5..xhi * 1.5).log_scale(), ylo..yhi)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(xlabel)
        .y_desc(ylabel)
        .label_style(("sans-serif", 14))
        .max_light_lines(0)
        .draw()
        .map_err(err)?;
    // SEC = NSEC.
    chart
        .draw_series(LineSeries::new([(xlo / 1.5, 1.0), (xhi * 1.5, 1.0)], BLACK.mix(0.4).stroke_width(1)))
        .map_err(err)?;
    for (i, (label, x, y)) in points.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        chart.draw_series(std::iter::once(Circle::new((*x, *y), 6, colour.filled()))).map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(label.clone(), (*x, *y), ("sans-serif", 14).into_font())))
            .map_err(err)?;
    }
    root.present().map_err(err)
}

struct Scatter<'a> {
    title: &'a str,
    xlabel: &'a str,
    ylabel: &'a str,
    points: &'a [(String, f64, f64)],
}

impl Chart for Scatter<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        draw_scatter(root, self.title, self.xlabel, self.ylabel, self.points)
    }
}

/// Writes `<stem>.svg` and `<stem>.png`: labelled points on a log-scale x axis, with y = 1 marked.
pub fn scatter(
    stem: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    points: &[(String, f64, f64)],
) -> Result<(), String> {
    write(stem, &Scatter { title, xlabel, ylabel, points })
}

/// Empirical distribution functions: for each labelled sample, the share of its values at or
/// below x, over x from 0 to `xmax`, with a vertical line at `mark`.
struct Distributions<'a> {
    title: &'a str,
    xlabel: &'a str,
    samples: &'a [(String, Vec<f64>)],
    xmax: f64,
    mark: (f64, &'a str),
}

impl Chart for Distributions<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(self.title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(60)
            .build_cartesian_2d(0f64..self.xmax, 0f64..1.0)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(self.xlabel)
            .y_desc("share of views at or below")
            .label_style(("sans-serif", 14))
            .max_light_lines(0)
            .draw()
            .map_err(err)?;
        let (x, label) = self.mark;
        chart.draw_series(LineSeries::new([(x, 0.0), (x, 1.0)], BLACK.mix(0.4).stroke_width(1))).map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(label.to_string(), (x, 0.04), ("sans-serif", 14).into_font())))
            .map_err(err)?;
        for (i, (name, values)) in self.samples.iter().enumerate() {
            let colour = COLOURS[i % COLOURS.len()];
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            let n = sorted.len().max(1) as f64;
            // A step at each value, cut at the axis' end.
            let mut steps = vec![(0.0, 0.0)];
            for (k, &v) in sorted.iter().enumerate().filter(|(_, &v)| v <= self.xmax) {
                steps.push((v, k as f64 / n));
                steps.push((v, (k + 1) as f64 / n));
            }
            let last = steps.last().map_or(0.0, |p| p.1);
            steps.push((self.xmax, last));
            line(&mut chart, steps, colour, name)?;
        }
        legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        root.present().map_err(err)
    }
}

/// Writes `<stem>.svg` and `<stem>.png`: the distribution function of each labelled sample over
/// [0, `xmax`], with a vertical line at `mark.0` labelled `mark.1`.
pub fn distributions(
    stem: &Path,
    title: &str,
    xlabel: &str,
    samples: &[(String, Vec<f64>)],
    xmax: f64,
    mark: (f64, &str),
) -> Result<(), String> {
    write(stem, &Distributions { title, xlabel, samples, xmax, mark })
}

/// Per-run values as dots, two columns per group (ours, theirs), with a horizontal line at
/// `mark`: run against run, where a mean would hide how many runs learned.
struct Dots<'a> {
    title: &'a str,
    ylabel: &'a str,
    groups: &'a [(String, [Vec<f64>; 2])],
    sides: [&'a str; 2],
    mark: (f64, &'a str),
}

impl Chart for Dots<'_> {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), String>
    where
        DB::ErrorType: 'static,
    {
        let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
        root.fill(&WHITE).map_err(err)?;
        let hi = self.groups.iter().flat_map(|(_, s)| s.iter().flatten()).fold(self.mark.0, |a, &b| a.max(b));
        let n = self.groups.len().max(1) as f64;
        let mut chart = ChartBuilder::on(&root)
            .caption(self.title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(44)
            .y_label_area_size(60)
            .build_cartesian_2d(0f64..n, 0f64..hi * 1.08 + 1e-3)
            .map_err(err)?;
        let names: Vec<&str> = self.groups.iter().map(|(g, _)| g.as_str()).collect();
        chart
            .configure_mesh()
            .y_desc(self.ylabel)
            .x_labels(names.len() * 2 + 1)
            .x_label_formatter(&|x| {
                let i = x.floor() as usize;
                let centre = (x - x.floor() - 0.5).abs() < 1e-6;
                names.get(i).filter(|_| centre).map_or(String::new(), |n| n.to_string())
            })
            .label_style(("sans-serif", 14))
            .max_light_lines(0)
            .disable_x_mesh()
            .draw()
            .map_err(err)?;
        let (y, label) = self.mark;
        chart.draw_series(LineSeries::new([(0.0, y), (n, y)], BLACK.mix(0.4).stroke_width(1))).map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(label.to_string(), (0.02, y), ("sans-serif", 13).into_font())))
            .map_err(err)?;
        for side in 0..2 {
            let colour = COLOURS[side];
            let dots: Vec<(f64, f64)> = self
                .groups
                .iter()
                .enumerate()
                .flat_map(|(i, (_, s))| {
                    let mut v = s[side].clone();
                    v.sort_by(f64::total_cmp);
                    // Spread across a band of the column by rank, so equal values stay apart.
                    let k = v.len().max(2) as f64 - 1.0;
                    let x0 = i as f64 + 0.18 + 0.36 * side as f64;
                    v.into_iter().enumerate().map(move |(j, y)| (x0 + 0.22 * j as f64 / k, y)).collect::<Vec<_>>()
                })
                .collect();
            chart
                .draw_series(dots.into_iter().map(|p| Circle::new(p, 4, colour.filled())))
                .map_err(err)?
                .label(self.sides[side])
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, colour.filled()));
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        root.present().map_err(err)
    }
}

/// Writes `<stem>.svg` and `<stem>.png`: for each group, the values of `sides[0]` and `sides[1]`
/// as two columns of dots, with a horizontal line at `mark.0` labelled `mark.1`.
pub fn dots(
    stem: &Path,
    title: &str,
    ylabel: &str,
    groups: &[(String, [Vec<f64>; 2])],
    sides: [&str; 2],
    mark: (f64, &str),
) -> Result<(), String> {
    write(stem, &Dots { title, ylabel, groups, sides, mark })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stem_with_a_dot_keeps_its_whole_name() {
        let dir = std::env::temp_dir().join(format!("sec-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let series = [Series { label: "SEC".into(), mean: vec![0.0, 1.0], se: vec![0.1, 0.1] }];
        for figure in ["x0.5-reward", "x0.5-entropy"] {
            curves(&dir.join(figure), figure, "y", &series).unwrap();
        }
        let mut names: Vec<String> =
            std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
        names.sort();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(names, ["x0.5-entropy.png", "x0.5-entropy.svg", "x0.5-reward.png", "x0.5-reward.svg"]);
    }
}
