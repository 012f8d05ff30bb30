//! `eval --plot`: the per-frame figures of an [`EvalReport`] as one chart of four panels (coherence,
//! Hausdorff distance, topology against the input, stage times), so a run can be judged at a glance
//! before its numbers are read. PNG or SVG by the file's extension; text is set in DejaVu Sans,
//! embedded, so the chart looks the same on every machine and needs no system fonts.

use super::{EvalError, EvalReport};
use crate::io::atomic_write;
use crate::propagate::PropagateError;
use crate::sequence::TRACK_FILE;
use crate::track::StageTimes;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// The chart's size in pixels.
const SIZE: (u32, u32) = (1200, 800);
/// DejaVu Sans (Bitstream Vera licence, `assets/fonts/DejaVuSans-LICENSE.txt`).
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
const FAMILY: &str = "sans-serif";

/// Draws `report` (and the stage times of each frame, when known) into `path`, a `.png` or `.svg`
/// file, atomically.
pub fn plot(
    report: &EvalReport,
    times: &[Option<StageTimes>],
    path: &Path,
) -> Result<(), EvalError> {
    let failed = |reason: String| EvalError::Plot {
        path: path.to_path_buf(),
        reason,
    };
    register_font().map_err(failed)?;
    match path.extension().and_then(|e| e.to_str()) {
        Some("svg") => {
            let mut text = String::new();
            {
                let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
                draw(&root, report, times).map_err(|e| failed(e.to_string()))?;
                root.present().map_err(|e| failed(e.to_string()))?;
            }
            atomic_write(path, |w| w.write_all(text.as_bytes()))?;
        }
        Some("png") => {
            let mut rgb = vec![0u8; 3 * SIZE.0 as usize * SIZE.1 as usize];
            {
                let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
                draw(&root, report, times).map_err(|e| failed(e.to_string()))?;
                root.present().map_err(|e| failed(e.to_string()))?;
            }
            atomic_write(path, |w| {
                let mut encoder = png::Encoder::new(w, SIZE.0, SIZE.1);
                encoder.set_color(png::ColorType::Rgb);
                encoder.set_depth(png::BitDepth::Eight);
                let mut writer = encoder.write_header().map_err(std::io::Error::other)?;
                writer
                    .write_image_data(&rgb)
                    .map_err(std::io::Error::other)?;
                writer.finish().map_err(std::io::Error::other)
            })?;
        }
        _ => {
            return Err(failed(
                "the chart's file must end in .png or .svg".to_string(),
            ));
        }
    }
    Ok(())
}

/// Each frame's stage times as `track.json` in `tracked` records them; empty when it has none.
pub fn stage_times(tracked: &Path) -> Result<Vec<Option<StageTimes>>, EvalError> {
    let path = tracked.join(TRACK_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => {
            return Err(EvalError::Tracked(PropagateError::Unreadable {
                path,
                reason: e.to_string(),
            }));
        }
    };
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| {
        EvalError::Tracked(PropagateError::Unreadable {
            path: path.clone(),
            reason: format!("not valid JSON: {e}"),
        })
    })?;
    Ok(json
        .get("frames")
        .and_then(|v| v.as_array())
        .map(|frames| {
            frames
                .iter()
                .map(|f| {
                    f.get("times")
                        .and_then(|t| serde_json::from_value(t.clone()).ok())
                })
                .collect()
        })
        .unwrap_or_default())
}

/// Registers the embedded font once per process.
fn register_font() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FAMILY, FontStyle::Normal, FONT)
                .map_err(|_| "the embedded font cannot be read".to_string())
        })
        .clone()
}

type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// One line of a panel: its name, colour and points.
struct Line {
    name: &'static str,
    colour: RGBColor,
    points: Vec<(f64, f64)>,
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    report: &EvalReport,
    times: &[Option<StageTimes>],
) -> Drawn<DB> {
    root.fill(&WHITE)?;
    let panels = root.split_evenly((2, 2));
    let frames = &report.frames;
    let series = |f: &dyn Fn(&super::FrameReport) -> Option<f64>| -> Vec<(f64, f64)> {
        frames
            .iter()
            .filter_map(|r| f(r).map(|y| (r.frame as f64, y)))
            .collect()
    };
    panel(
        &panels[0],
        "Coherence: vertices carried over",
        "% of the frame",
        &[Line {
            name: "carried over",
            colour: BLUE,
            points: series(&|r| r.coherence.map(|c| 100.0 * c)),
        }],
        frames.len(),
    )?;
    panel(
        &panels[1],
        "Hausdorff distance to the input",
        "input mean edge lengths",
        &[
            Line {
                name: "Hausdorff",
                colour: RED,
                points: series(&|r| Some(f64::from(r.hausdorff))),
            },
            Line {
                name: "mean distance",
                colour: RGBColor(230, 140, 0),
                points: series(&|r| Some(f64::from(r.mean_distance))),
            },
            Line {
                name: "bar",
                colour: RGBColor(120, 120, 120),
                points: series(&|_| Some(f64::from(report.max_hausdorff))),
            },
        ],
        frames.len(),
    )?;
    panel(
        &panels[2],
        "Topology: components and Euler characteristic",
        "count",
        &[
            Line {
                name: "components",
                colour: BLUE,
                points: series(&|r| Some(r.components as f64)),
            },
            Line {
                name: "input components",
                colour: RGBColor(120, 170, 255),
                points: series(&|r| Some(r.input_components as f64)),
            },
            Line {
                name: "Euler characteristic",
                colour: RGBColor(0, 140, 60),
                points: series(&|r| Some(r.euler as f64)),
            },
            Line {
                name: "input Euler",
                colour: RGBColor(120, 210, 140),
                points: series(&|r| Some(r.input_euler as f64)),
            },
        ],
        frames.len(),
    )?;
    let stage = |f: fn(&StageTimes) -> f64| -> Vec<(f64, f64)> {
        times
            .iter()
            .enumerate()
            .filter_map(|(k, t)| t.as_ref().map(|t| (k as f64, f(t))))
            .collect()
    };
    panel(
        &panels[3],
        "Time per stage",
        "milliseconds",
        &[
            Line {
                name: "register",
                colour: BLUE,
                points: stage(|t| t.register),
            },
            Line {
                name: "improve",
                colour: RGBColor(230, 140, 0),
                points: stage(|t| t.improve),
            },
            Line {
                name: "topology",
                colour: RED,
                points: stage(|t| t.topology_self + t.topology_target),
            },
            Line {
                name: "sub-grid match",
                colour: RGBColor(0, 140, 60),
                points: stage(|t| t.reconcile),
            },
            Line {
                name: "total",
                colour: BLACK,
                points: stage(|t| t.total),
            },
        ],
        frames.len(),
    )
}

/// One panel: lines over the frames, the y range fitted to them (from 0 when all are positive).
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    unit: &str,
    lines: &[Line],
    frames: usize,
) -> Drawn<DB> {
    let values = || lines.iter().flat_map(|l| l.points.iter().map(|p| p.1));
    let low = values().fold(0.0f64, f64::min);
    let high = values().fold(low + 1.0, f64::max);
    let pad = 0.05 * (high - low);
    let x_end = (frames.max(2) - 1) as f64;
    let mut chart = ChartBuilder::on(area)
        .caption(title, (FAMILY, 18))
        .margin(10)
        .x_label_area_size(36)
        .y_label_area_size(56)
        .build_cartesian_2d(
            0.0..x_end,
            (low - if low < 0.0 { pad } else { 0.0 })..high + pad,
        )?;
    chart
        .configure_mesh()
        .x_desc("frame")
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_desc(unit)
        .label_style((FAMILY, 12))
        .draw()?;
    for line in lines.iter().filter(|l| !l.points.is_empty()) {
        let colour = line.colour;
        chart
            .draw_series(LineSeries::new(
                line.points.iter().copied(),
                colour.stroke_width(2),
            ))?
            .label(line.name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2))
            });
    }
    chart
        .configure_series_labels()
        .label_font((FAMILY, 12))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_embedded_font_registers() {
        assert_eq!(register_font(), Ok(()));
    }
}
