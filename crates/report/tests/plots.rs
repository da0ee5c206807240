//! Plots read back by independent readers: the SVG parsed as XML
//! (roxmltree), the PNG decoded (png).
//!
//! What plotters emits, and these tests rely on: one `<text>` per string
//! drawn (title lines, axis titles, tick labels, legend label lines, marker
//! labels), one `<polyline>` per path. Grid, axis, tick and marker lines are
//! polylines of stroke-width 1; the data lines are the only polylines of
//! stroke-width [`LINE_WIDTH`] (2): one per non-empty series in the plot (as
//! many points as the series) and one of two points as its legend sample.
//! Joint-map cells are filled `<rect>`s.
//!
//! Text boxes are measured here with `ab_glyph` from the font file the crate
//! embeds: a `<text>` of `font-size` f was asked of plotters at 1.24 f pixels
//! (plotters writes size / 1.24); its width is the sum of the glyph advances
//! and kerning at that pixel size (what the PNG draws); its height covers
//! both the PNG's glyph box and the SVG's (baseline from `dy`, ascent and
//! descent at an em of f).

use ab_glyph::{Font, FontRef, ScaleFont};
use axijoint_report::plots::{
    plot_convergence, plot_joint_map, plot_profile, plot_profile_with, Axis, Marker, ProfilePlot, Series,
    LINE_WIDTH, PALETTE, SIZE, STATE_COLORS, STATE_LABELS,
};
use axijoint_report::ReportError;
use axijoint_solver::joint_law::JointState;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn hex((r, g, b): (u8, u8, u8)) -> String {
    format!("#{r:02X}{g:02X}{b:02X}")
}

/// The files of `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn paths(dir: &Path, stem: &str) -> (PathBuf, PathBuf) {
    (dir.join(format!("{stem}.svg")), dir.join(format!("{stem}.png")))
}

/// A parsed SVG: its text strings and its data polylines.
struct Svg {
    /// Width and height.
    size: (u32, u32),
    texts: BTreeSet<String>,
    /// The texts in document order with their boxes `[x0, x1, y0, y1]`.
    placed: Vec<(String, [f64; 4])>,
    /// (stroke colour upper case, dashed, number of points) of each polyline
    /// of the data stroke width.
    lines: Vec<(String, bool, usize)>,
    /// The same polylines in full.
    strokes: Vec<Stroke>,
    /// Fill colour (upper case) of each filled rectangle.
    rect_fills: Vec<String>,
}

/// A data polyline: stroke colour, `stroke-dasharray` (empty when solid),
/// points.
type Stroke = (String, String, Vec<(f64, f64)>);

fn read_svg(path: &Path) -> Svg {
    let text = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("the SVG is well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let dim = |a: &str| root.attribute(a).unwrap().parse::<u32>().unwrap();
    let size = (dim("width"), dim("height"));
    assert_eq!(size.0, SIZE.0, "the width is fixed");
    assert!(size.1 >= SIZE.1, "the height only grows");
    assert!(
        !text.contains("NaN") && !text.contains("inf"),
        "no NaN or infinity in the SVG"
    );
    let mut texts = BTreeSet::new();
    let mut placed_texts = Vec::new();
    let mut strokes = Vec::new();
    let mut lines = Vec::new();
    let mut rect_fills = Vec::new();
    let mut placed = BTreeSet::new();
    let width = LINE_WIDTH.to_string();
    for n in root.descendants().filter(|n| n.is_element()) {
        match n.tag_name().name() {
            "text" => {
                let t = n.text().unwrap_or("").trim().to_owned();
                assert!(!t.is_empty(), "no empty text element");
                let at = (
                    t.clone(),
                    n.attribute("x").unwrap().to_owned(),
                    n.attribute("y").unwrap().to_owned(),
                );
                assert!(placed.insert(at), "{t:?} drawn twice at one place");
                placed_texts.push((t.clone(), text_box(&n, &t)));
                texts.insert(t);
            }
            "polyline" => {
                let w = n.attribute("stroke-width").unwrap();
                assert!(w == "1" || w == width, "unexpected stroke width {w}");
                if w == width {
                    let points = n.attribute("points").unwrap().split_whitespace().count();
                    let dashed = n.attribute("stroke-dasharray").is_some();
                    let stroke = n.attribute("stroke").unwrap().to_uppercase();
                    lines.push((stroke.clone(), dashed, points));
                    let xy = n
                        .attribute("points")
                        .unwrap()
                        .split_whitespace()
                        .map(|p| {
                            let (x, y) = p.split_once(',').unwrap();
                            (x.parse().unwrap(), y.parse().unwrap())
                        })
                        .collect();
                    let dash = n.attribute("stroke-dasharray").unwrap_or("").to_owned();
                    strokes.push((stroke, dash, xy));
                }
            }
            "rect" if n.attribute("fill") != Some("none") => {
                rect_fills.push(n.attribute("fill").unwrap().to_uppercase());
            }
            _ => {}
        }
    }
    Svg {
        size,
        texts,
        placed: placed_texts,
        lines,
        strokes,
        rect_fills,
    }
}

/// The embedded font, read from the crate's file.
fn font() -> FontRef<'static> {
    FontRef::try_from_slice(include_bytes!("../assets/DejaVuSans.ttf")).unwrap()
}

/// The box `[x0, x1, y0, y1]` of a `<text>` element showing `t` (see the
/// module documentation), rotated as its `transform` says.
fn text_box(n: &roxmltree::Node, t: &str) -> [f64; 4] {
    let num = |a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
    let (x, y, em) = (num("x"), num("y"), num("font-size"));
    let f = font();
    let px = em * 1.24;
    let scaled = f.as_scaled(px as f32);
    let mut w = 0.0f32;
    let mut prev = None;
    for c in t.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            w += scaled.kern(p, id);
        }
        w += scaled.h_advance(id);
        prev = Some(id);
    }
    let w = f64::from(w);
    let (x0, x1) = match n.attribute("text-anchor").unwrap() {
        "start" => (x, x + w),
        "middle" => (x - w / 2.0, x + w / 2.0),
        "end" => (x - w, x),
        other => panic!("text-anchor {other}"),
    };
    let upem = f64::from(f.units_per_em().unwrap());
    let (asc, desc) = (
        f64::from(f.ascent_unscaled()) / upem,
        f64::from(f.descent_unscaled()) / upem,
    );
    let x_height = f64::from(f.outline(f.glyph_id('x')).unwrap().bounds.max.y) / upem;
    let (png, baseline) = match n.attribute("dy").unwrap() {
        "0.76em" => ((y, y + px), y + 0.76 * em),
        "0.5ex" => ((y - px / 2.0, y + px / 2.0), y + 0.5 * x_height * em),
        "-0.5ex" => ((y - px, y), y - 0.5 * x_height * em),
        other => panic!("dy {other}"),
    };
    let (y0, y1) = (png.0.min(baseline - asc * em), png.1.max(baseline - desc * em));
    let Some(rot) = n.attribute("transform") else {
        return [x0, x1, y0, y1];
    };
    // rotate(A, cx, cy): A degrees clockwise on the screen about (cx, cy).
    let args: Vec<f64> = rot
        .trim_start_matches("rotate(")
        .trim_end_matches(')')
        .split(',')
        .map(|v| v.trim().parse().unwrap())
        .collect();
    let (sin, cos) = args[0].to_radians().sin_cos();
    let corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(px, py)| {
        let (dx, dy) = (px - args[1], py - args[2]);
        (args[1] + dx * cos - dy * sin, args[2] + dx * sin + dy * cos)
    });
    let xs = corners.map(|c| c.0);
    let ys = corners.map(|c| c.1);
    let lo = |v: [f64; 4]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = |v: [f64; 4]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    [lo(xs), hi(xs), lo(ys), hi(ys)]
}

/// Decodes an RGB(A) PNG: (width, height, pixels as RGB).
fn read_png(path: &Path) -> (u32, u32, Vec<[u8; 3]>) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("unexpected PNG colour type {other:?}"),
    };
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let pixels = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width, info.height, pixels)
}

/// Checks the PNG's size and that it is not blank; returns its pixels.
fn check_png(path: &Path) -> Vec<[u8; 3]> {
    let (w, h, px) = read_png(path);
    let svg = read_svg(&path.with_extension("svg"));
    assert_eq!((w, h), svg.size, "the PNG has the SVG's size");
    assert!(px.iter().any(|p| *p != px[0]), "not all pixels the same colour");
    let dark = px
        .iter()
        .filter(|p| p.iter().map(|&c| u32::from(c)).sum::<u32>() < 200)
        .count();
    assert!(dark > 2000, "text and axes give dark pixels, found {dark}");
    px
}

fn count_color(px: &[[u8; 3]], (r, g, b): (u8, u8, u8)) -> usize {
    px.iter().filter(|p| **p == [r, g, b]).count()
}

fn series(label: &str, n: usize, dashed: bool, color: usize, x0: f64, f: impl Fn(f64) -> f64) -> Series {
    Series {
        label: label.to_owned(),
        points: (0..n)
            .map(|i| {
                let x = x0 + i as f64 * 0.1;
                (x, f(x))
            })
            .collect(),
        color,
        dash: usize::from(dashed),
    }
}

#[test]
fn profile_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = paths(dir.path(), "cut_a_theta180");
    let all = vec![
        series("with joint, pile", 6, false, 0, 0.0, |x| -2.0 + x),
        series("with joint, footing", 26, false, 1, 0.5, |_| 0.0),
        series("without joint, pile", 7, true, 0, 0.0, |x| -1.5 + x),
        series("without joint, footing", 25, true, 1, 0.6, |x| 0.8 / x),
        series("empty, skipped", 0, false, 2, 0.0, |x| x),
    ];
    plot_profile(
        &svg,
        Some(&png),
        "Cut a-a, theta = 180 deg",
        "r (m)",
        "sigma_z (MPa)",
        &all,
    )
    .unwrap();
    assert_eq!(listing(dir.path()), ["cut_a_theta180.png", "cut_a_theta180.svg"]);

    let doc = read_svg(&svg);
    for t in ["Cut a-a, theta = 180 deg", "r (m)", "sigma_z (MPa)"] {
        assert!(doc.texts.contains(t), "text {t:?} in {:?}", doc.texts);
    }
    for s in &all[..4] {
        assert!(doc.texts.contains(&s.label), "legend label {:?}", s.label);
    }
    assert!(!doc.texts.contains("empty, skipped"));
    assert_eq!(
        doc.lines.len(),
        2 * 4,
        "a line and a legend sample per non-empty series"
    );
    for s in &all[..4] {
        let key = (hex(PALETTE[s.color]), s.dash == 1);
        let mine: Vec<usize> = doc
            .lines
            .iter()
            .filter(|l| (l.0.clone(), l.1) == key)
            .map(|l| l.2)
            .collect();
        assert_eq!(
            mine,
            [s.points.len(), 2],
            "series {:?}: its line, then its legend sample",
            s.label
        );
    }

    let px = check_png(&png);
    assert!(count_color(&px, PALETTE[0]) > 100, "blue lines drawn");
    assert!(count_color(&px, PALETTE[1]) > 100, "vermillion lines drawn");
    assert_eq!(count_color(&px, PALETTE[2]), 0, "the empty series draws nothing");
}

#[test]
fn single_point_and_empty_profiles_draw() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = paths(dir.path(), "p");
    let one = vec![series("one point", 1, false, 3, 1.0, |_| 2.0)];
    plot_profile(&svg, Some(&png), "One point", "x (m)", "y (MPa)", &one).unwrap();
    let doc = read_svg(&svg);
    assert_eq!(doc.lines.iter().map(|l| l.2).collect::<Vec<_>>(), [1, 2]);
    assert!(
        count_color(&check_png(&png), PALETTE[3]) > 20,
        "a dot for the point"
    );

    plot_profile(&svg, Some(&png), "Nothing", "x (m)", "y (MPa)", &[]).unwrap();
    let doc = read_svg(&svg);
    assert!(doc.texts.contains("Nothing") && doc.lines.is_empty());
    check_png(&png);

    plot_joint_map(&svg, Some(&png), "No joint data", &[], &[], &[]).unwrap();
    assert!(read_svg(&svg).texts.contains("No joint data"));
    check_png(&png);
    assert_eq!(
        listing(dir.path()),
        ["p.png", "p.svg"],
        "replaced in place, nothing left over"
    );
}

#[test]
fn without_a_png_path_only_the_svg_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, _) = paths(dir.path(), "q");
    let one = vec![series("one point", 1, false, 3, 1.0, |_| 2.0)];
    plot_profile(&svg, None, "One point", "x (m)", "y (MPa)", &one).unwrap();
    plot_convergence(&svg, None, "c", &[("run".into(), vec![(1, 0.5), (2, 0.1)])]).unwrap();
    plot_joint_map(&svg, None, "No joint data", &[], &[], &[]).unwrap();
    assert!(read_svg(&svg).texts.contains("No joint data"));
    assert_eq!(listing(dir.path()), ["q.svg"]);
}

#[test]
fn convergence_svg_and_png() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = paths(dir.path(), "convergence");
    let decay =
        |n: u32, rate: f64| -> Vec<(u32, f64)> { (1..=n).map(|i| (i, rate.powi(i as i32 - 1))).collect() };
    let mut exact = decay(12, 0.5);
    exact.push((13, 0.0)); // a zero residual: drawn on the bottom edge
    let runs = vec![
        ("frictionless".to_owned(), decay(40, 0.85)),
        ("no slip".to_owned(), exact),
        ("not run".to_owned(), vec![]),
    ];
    plot_convergence(&svg, Some(&png), "Convergence of the residual ratio", &runs).unwrap();
    assert_eq!(listing(dir.path()), ["convergence.png", "convergence.svg"]);

    let doc = read_svg(&svg);
    for t in [
        "Convergence of the residual ratio",
        "frictionless",
        "no slip",
        "iteration",
    ] {
        assert!(doc.texts.contains(t), "text {t:?} in {:?}", doc.texts);
    }
    assert!(!doc.texts.contains("not run"));
    // 0.85^39 = 1.8e-3 and 0.5^11 = 4.9e-4: decades 1e-4 .. 1, one lower for the zero.
    assert!(
        doc.texts.contains("1e-5") && doc.texts.contains("1"),
        "{:?}",
        doc.texts
    );
    assert!(!doc.texts.contains("1e-6"));
    assert_eq!(doc.lines.len(), 4);
    for (k, (_, pts)) in runs[..2].iter().enumerate() {
        let mine: Vec<usize> = doc
            .lines
            .iter()
            .filter(|l| l.0 == hex(PALETTE[k]))
            .map(|l| l.2)
            .collect();
        assert_eq!(mine, [pts.len(), 2]);
    }
    assert!(doc.lines.iter().all(|l| !l.1), "convergence lines are solid");

    let px = check_png(&png);
    assert!(count_color(&px, PALETTE[0]) > 100 && count_color(&px, PALETTE[1]) > 100);
}

#[test]
fn joint_map_svg_and_png() {
    use JointState::{Open, Slip, Stick};
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = paths(dir.path(), "joint_side");
    let s: Vec<f64> = (0..10).map(|i| 0.05 + 0.1 * f64::from(i)).collect();
    let theta = [0.0, 45.0, 90.0, 135.0, 180.0];
    let states = vec![
        vec![Stick; 10],
        [vec![Stick; 4], vec![Slip; 6]].concat(),
        [vec![Slip; 3], vec![Stick; 2], vec![Slip; 5]].concat(),
        [vec![Open; 5], vec![Slip; 5]].concat(),
        vec![Open; 10],
    ];
    plot_joint_map(&svg, Some(&png), "Joint pile side: states", &s, &theta, &states).unwrap();
    assert_eq!(listing(dir.path()), ["joint_side.png", "joint_side.svg"]);

    let doc = read_svg(&svg);
    for t in [
        "Joint pile side: states",
        "theta (deg)",
        "0",
        "45",
        "90",
        "135",
        "180",
    ] {
        assert!(doc.texts.contains(t), "text {t:?} in {:?}", doc.texts);
    }
    for label in STATE_LABELS {
        assert!(doc.texts.contains(label), "legend label {label}");
    }
    // Runs of equal states: stick 1 + 1 + 1, slip 1 + 2 + 1, open 1 + 1; plus a legend box each.
    for ((_, c), runs) in STATE_COLORS.iter().zip([3, 4, 2]) {
        let n = doc.rect_fills.iter().filter(|f| **f == hex(*c)).count();
        assert_eq!(n, runs + 1, "cells of colour {}", hex(*c));
    }

    let px = check_png(&png);
    for (state, c) in STATE_COLORS {
        assert!(count_color(&px, c) > 500, "{state:?} cells drawn");
    }
}

#[test]
fn non_finite_and_bad_shapes_are_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = paths(dir.path(), "bad");
    let mut s = series("pile", 5, false, 0, 0.0, |x| x);
    s.points[3].1 = f64::NAN;
    let e = plot_profile(&svg, Some(&png), "t", "x", "y", &[s]).unwrap_err();
    assert!(matches!(e, ReportError::NotFinite { .. }), "{e}");
    let mut s = series("pile", 5, false, 0, 0.0, |x| x);
    s.points[0].0 = f64::INFINITY;
    assert!(matches!(
        plot_profile(&svg, Some(&png), "t", "x", "y", &[s]),
        Err(ReportError::NotFinite { .. })
    ));

    let runs = vec![("a".to_owned(), vec![(1, 1.0), (2, f64::NAN)])];
    assert!(matches!(
        plot_convergence(&svg, Some(&png), "t", &runs),
        Err(ReportError::NotFinite { .. })
    ));
    let runs = vec![("a".to_owned(), vec![(1, 1.0), (2, f64::NEG_INFINITY)])];
    assert!(matches!(
        plot_convergence(&svg, Some(&png), "t", &runs),
        Err(ReportError::NotFinite { .. })
    ));

    let st = vec![vec![JointState::Stick; 2]; 2];
    assert!(matches!(
        plot_joint_map(&svg, Some(&png), "t", &[0.0, f64::NAN], &[0.0, 90.0], &st),
        Err(ReportError::NotFinite { .. })
    ));
    assert!(matches!(
        plot_joint_map(&svg, Some(&png), "t", &[0.0, 1.0], &[0.0, f64::INFINITY], &st),
        Err(ReportError::NotFinite { .. })
    ));
    for (s, theta) in [
        (&[0.0, 1.0, 2.0][..], &[0.0, 90.0][..]),
        (&[0.0, 1.0], &[0.0, 90.0, 180.0]),
        (&[1.0, 0.0], &[0.0, 90.0]),
    ] {
        assert!(matches!(
            plot_joint_map(&svg, Some(&png), "t", s, theta, &st),
            Err(ReportError::Input(_))
        ));
    }
    assert!(
        listing(dir.path()).is_empty(),
        "no file left behind: {:?}",
        listing(dir.path())
    );
}

/// The indices of the consecutive texts (from document order) that show
/// `label`, one line each: joined by a space where it was wrapped at one,
/// directly where a word was broken.
fn find_label(texts: &[(String, [f64; 4])], label: &str) -> Option<Vec<usize>> {
    'start: for i in 0..texts.len() {
        let mut acc = texts[i].0.clone();
        let mut used = vec![i];
        while acc != label {
            let j = used[used.len() - 1] + 1;
            let Some(rest) = label.strip_prefix(acc.as_str()) else {
                continue 'start;
            };
            let Some((next, _)) = texts.get(j) else {
                continue 'start;
            };
            if rest
                .strip_prefix(' ')
                .is_some_and(|r| r.starts_with(next.as_str()))
            {
                acc = format!("{acc} {next}");
            } else if rest.starts_with(next.as_str()) {
                acc.push_str(next);
            } else {
                continue 'start;
            }
            used.push(j);
        }
        return Some(used);
    }
    None
}

fn overlap(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] < b[1] && b[0] < a[1] && a[2] < b[3] && b[2] < a[3]
}

/// The checks of a plot's text: every text box inside the canvas and apart
/// from every other; each of `legend` and `others` shown in full (perhaps
/// on several lines), the legend's apart from the data lines (polylines of
/// more than two points); the PNG's outer 2-pixel frame white (nothing cut
/// at an edge). Returns the SVG.
fn check_text_fits(svg: &Path, png: &Path, legend: &[&str], others: &[&str]) -> Svg {
    let doc = read_svg(svg);
    let (w, h) = (f64::from(doc.size.0), f64::from(doc.size.1));
    for (t, b) in &doc.placed {
        assert!(
            b[0] >= 0.0 && b[1] <= w && b[2] >= 0.0 && b[3] <= h,
            "{t:?} at {b:?} is not inside the {w} x {h} canvas"
        );
    }
    for (i, (t, a)) in doc.placed.iter().enumerate() {
        for (u, b) in &doc.placed[i + 1..] {
            assert!(!overlap(a, b), "{t:?} at {a:?} overlaps {u:?} at {b:?}");
        }
    }
    let data: Vec<&(f64, f64)> = doc
        .strokes
        .iter()
        .filter(|l| l.2.len() > 2)
        .flat_map(|l| &l.2)
        .collect();
    let lo = |f: fn(&(f64, f64)) -> f64| data.iter().map(|p| f(p)).fold(f64::INFINITY, f64::min);
    let hi = |f: fn(&(f64, f64)) -> f64| data.iter().map(|p| f(p)).fold(f64::NEG_INFINITY, f64::max);
    let data_box = [lo(|p| p.0), hi(|p| p.0), lo(|p| p.1), hi(|p| p.1)];
    for label in others {
        assert!(
            find_label(&doc.placed, label).is_some(),
            "{label:?} is not shown in full"
        );
    }
    for label in legend {
        let used = find_label(&doc.placed, label).unwrap_or_else(|| panic!("{label:?} is not shown in full"));
        for i in used {
            let (t, b) = &doc.placed[i];
            assert!(
                !overlap(b, &data_box),
                "legend text {t:?} at {b:?} over the data {data_box:?}"
            );
        }
    }
    let (pw, ph, px) = read_png(png);
    assert_eq!((pw, ph), doc.size);
    let (pw, ph) = (pw as usize, ph as usize);
    for y in 0..ph {
        for x in 0..pw {
            if x < 2 || y < 2 || x + 2 >= pw || y + 2 >= ph {
                assert_eq!(
                    px[y * pw + x],
                    [255; 3],
                    "PNG pixel ({x}, {y}) on the edge is drawn"
                );
            }
        }
    }
    doc
}

/// Each data style `(stroke, dash array)` drawn exactly twice (the line and
/// its legend sample), and as many styles as series.
fn check_distinct_styles(doc: &Svg, n_series: usize) {
    let mut count: std::collections::BTreeMap<(String, String), usize> = Default::default();
    for (stroke, dash, _) in &doc.strokes {
        *count.entry((stroke.clone(), dash.clone())).or_default() += 1;
    }
    assert_eq!(count.len(), n_series, "one (colour, dash) per series: {count:?}");
    assert!(count.values().all(|&n| n == 2), "{count:?}");
}

/// The worst cases: 16 series (their requested colours and dashes repeat),
/// labels too long for a panel beside the plot, one word wider than the
/// canvas, a three-line title, markers close together and at an end; 12
/// convergence runs with long path labels; a joint map with a long title.
#[test]
fn worst_case_text_fits_and_every_series_has_its_own_style() {
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = paths(dir.path(), "worst");
    let body = "precast_concrete_pile_with_a_long_name";
    let mut all: Vec<Series> = (0..16u32)
        .map(|k| {
            let t = 22.5 * f64::from(k / 2);
            let variant = if k % 2 == 0 {
                "with joint".to_owned()
            } else {
                format!("without joint (bonded run of out/runs/case_{k}/pile_bonded)")
            };
            let mut s = series(
                &format!("theta {t} deg, {body}, {variant}"),
                61,
                false,
                0,
                0.0,
                |x| (x + f64::from(k)).sin() * (1.0 + f64::from(k)),
            );
            (s.color, s.dash) = (k as usize % 3, k as usize % 2);
            s
        })
        .collect();
    all[3].label = format!("{}_unbroken", "x".repeat(140));
    all[5].label = "a".to_owned();
    all.push(series("empty, skipped", 0, false, 2, 0.0, |x| x));
    let title = "Cut a-very-long-cut-name: sigma_z at r = 0.45 m, z = 0 to -12 m; \
                 theta = 0, 22.5, 45, 67.5, 90, 112.5, 135, 157.5 deg, a title that needs three \
                 lines on the canvas of this plot";
    let markers = [
        (0.5, 0.5, "joint pile_shaft"),
        (0.55, 0.55, "joint pile_shaft_lower"),
        (2.0, 2.5, "joint along the cut"),
        (6.0, 6.0, "joint pile_toe"),
    ]
    .map(|(from, to, label)| Marker {
        axis: Axis::X,
        from,
        to,
        label: label.to_owned(),
    });
    let plot = ProfilePlot {
        title,
        x_label: "distance along the cut (m)",
        y_label: "sigma_z (MPa)",
        series: &all,
        markers: &markers,
        position: Axis::X,
    };
    plot_profile_with(&svg, Some(&png), &plot).unwrap();
    let labels: Vec<&str> = all[..16].iter().map(|s| s.label.as_str()).collect();
    let others: Vec<&str> = markers.iter().map(|m| m.label.as_str()).chain([title]).collect();
    let doc = check_text_fits(&svg, &png, &labels, &others);
    assert!(doc.size.1 > SIZE.1, "the canvas grew: {:?}", doc.size);
    assert!(!doc.texts.contains("empty, skipped"));
    check_distinct_styles(&doc, 16);

    // The same along y (a cut along z), markers across it.
    let vertical: Vec<Series> = all
        .iter()
        .map(|s| Series {
            points: s.points.iter().map(|&(x, y)| (y, -x)).collect(),
            ..s.clone()
        })
        .collect();
    let markers_y: Vec<Marker> = markers
        .iter()
        .map(|m| Marker {
            axis: Axis::Y,
            from: -m.from,
            to: -m.to,
            ..m.clone()
        })
        .collect();
    let plot = ProfilePlot {
        x_label: "sigma_z (MPa)",
        y_label: "z (m)",
        series: &vertical,
        markers: &markers_y,
        position: Axis::Y,
        ..plot
    };
    plot_profile_with(&svg, Some(&png), &plot).unwrap();
    check_distinct_styles(&check_text_fits(&svg, &png, &labels, &others), 16);

    // Twelve runs of one scene, labelled by long paths.
    let runs: Vec<(String, Vec<(u32, f64)>)> = (0..12)
        .map(|k| {
            (
                format!("/home/someone/projects/piles/parameter_study/case_{k:02}/out/pile_footing_scene"),
                (1..=20 + k).map(|i| (i, 0.7f64.powi(i as i32))).collect(),
            )
        })
        .collect();
    let (svg, png) = paths(dir.path(), "runs");
    plot_convergence(&svg, Some(&png), title, &runs).unwrap();
    let labels: Vec<&str> = runs.iter().map(|r| r.0.as_str()).collect();
    let doc = check_text_fits(&svg, &png, &labels, &[title]);
    check_distinct_styles(&doc, 12);

    let (svg, png) = paths(dir.path(), "map");
    let st = vec![vec![JointState::Stick, JointState::Open]; 2];
    plot_joint_map(&svg, Some(&png), title, &[0.0, 1.0], &[0.0, 180.0], &st).unwrap();
    check_text_fits(&svg, &png, &STATE_LABELS, &[title]);
}

/// Renders sample plots into `$AXIJOINT_PLOTS_DIR` for a look by eye:
/// `AXIJOINT_PLOTS_DIR=/tmp/plots cargo test -p axijoint-report --test plots -- --ignored`.
#[test]
#[ignore = "writes sample plots for review"]
fn render_samples_for_review() {
    let dir = PathBuf::from(std::env::var("AXIJOINT_PLOTS_DIR").expect("set AXIJOINT_PLOTS_DIR"));
    std::fs::create_dir_all(&dir).unwrap();
    let a = 0.5;
    let sample =
        |label: &str, from: f64, to: f64, dashed: bool, color: usize, f: &dyn Fn(f64) -> f64| Series {
            label: label.to_owned(),
            points: (0..=50)
                .map(|i| from + (to - from) * f64::from(i) / 50.0)
                .map(|r| (r, f(r)))
                .collect(),
            color,
            dash: usize::from(dashed),
        };
    let prof = vec![
        sample("with joint, pile", 0.0, a, false, 0, &|r| -1.2 + 2.6 * r),
        sample("with joint, footing", a, 3.0, false, 1, &|_| 0.0),
        sample("without joint, pile", 0.0, a, true, 0, &|r| -0.9 + 2.2 * r),
        sample("without joint, footing", a, 3.0, true, 1, &|r| {
            0.55 * (a / r).powi(2)
        }),
    ];
    let (svg, png) = paths(&dir, "profile");
    plot_profile(
        &svg,
        Some(&png),
        "Cut a-a (z = 0.75 m), theta = 180 deg",
        "r (m)",
        "sigma_z (MPa)",
        &prof,
    )
    .unwrap();

    // Linear to 20 %, then hyperbolic, as the paper's Fig. 8.
    let fig8 = |n: u32, knee: f64| -> Vec<(u32, f64)> {
        (1..=n)
            .map(|i| {
                let i = f64::from(i);
                (
                    i as u32,
                    if i <= knee {
                        1.0 - 0.8 * (i - 1.0) / (knee - 1.0)
                    } else {
                        0.2 * knee / i
                    },
                )
            })
            .collect()
    };
    let runs = vec![
        ("frictionless (C = 0, phi = 0)".to_owned(), fig8(80, 20.0)),
        ("no slip (C = 2.0, phi = 30)".to_owned(), fig8(30, 12.0)),
    ];
    let (svg, png) = paths(&dir, "convergence");
    plot_convergence(&svg, Some(&png), "Residual ratio (Fig. 8)", &runs).unwrap();

    use JointState::{Open, Slip, Stick};
    let s: Vec<f64> = (0..20).map(|i| 0.025 + 0.05 * f64::from(i)).collect();
    let theta = [0.0, 45.0, 90.0, 135.0, 180.0];
    let states: Vec<Vec<JointState>> = theta
        .iter()
        .map(|&t: &f64| {
            s.iter()
                .map(|&x| {
                    if t > 100.0 && x < 0.7 {
                        Open
                    } else if t > 40.0 && x > 0.4 {
                        Slip
                    } else {
                        Stick
                    }
                })
                .collect()
        })
        .collect();
    let (svg, png) = paths(&dir, "joint_map");
    plot_joint_map(
        &svg,
        Some(&png),
        "Joint 'pile_side' (s in m)",
        &s,
        &theta,
        &states,
    )
    .unwrap();
}
