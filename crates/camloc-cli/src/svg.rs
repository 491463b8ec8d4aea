//! SVG drawings: a 2D skeleton with its predicted viewpoint on a sphere diagram, and a
//! reconstruction (input, reprojection, three views of the 3D skeleton).

use std::fmt::Write;

use camloc::geometry::{
    CameraLabel, CameraSet, Matrix3, Vector3, Viewpoint, look_at_origin, sphere_point,
};
use camloc::skeleton::{LIMBS, Landmark, PartialPose2, Pose2, Pose3};
use camloc::{Localization, SmoothedFrame};

mod caption;

use caption::{CAPTION_LINE_PX, caption_lines};

const LEFT: &str = "#1f77b4";
const RIGHT: &str = "#d62728";
const CENTRE: &str = "#333333";

/// Colour of a limb: blue for the body's left, red for its right, grey for the centre line.
fn limb_colour(child: Landmark) -> &'static str {
    let name = child.name();
    if name.starts_with("left") {
        LEFT
    } else if name.starts_with("right") {
        RIGHT
    } else {
        CENTRE
    }
}

/// Fits 2D points into the box `(x, y, w, h)`, keeping the aspect ratio; returns the mapping.
fn fit_box(points: &[[f64; 2]], x: f64, y: f64, w: f64, h: f64) -> impl Fn([f64; 2]) -> [f64; 2] {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points
        .iter()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
    {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if !lo[0].is_finite() {
        lo = [0.0; 2];
        hi = [1.0; 2];
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-12);
    let s = 0.9 * w.min(h) / span;
    let cx = x + w / 2.0 - s * (lo[0] + hi[0]) / 2.0;
    let cy = y + h / 2.0 - s * (lo[1] + hi[1]) / 2.0;
    move |p: [f64; 2]| [cx + s * p[0], cy + s * p[1]]
}

/// Draws the limbs of a (possibly partial) 2D pose already mapped to SVG coordinates: with
/// `band`, as a pale band 7 wide (an input under its reprojection, so that the residuals
/// show), else as lines `width` wide with the joints dotted, the joints `filled[i]` (filled
/// in, not measured) as hollow rings.
fn draw_skeleton(
    svg: &mut String,
    points: &[Option<[f64; 2]>; 15],
    band: bool,
    width: f64,
    filled: &[bool; 15],
) {
    let (width, opacity) = if band { (7.0, 0.3) } else { (width, 1.0) };
    for (a, b) in LIMBS {
        if let (Some(p), Some(q)) = (points[a.index()], points[b.index()]) {
            let _ = writeln!(
                svg,
                r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{}" stroke-width="{width}" stroke-opacity="{opacity}" stroke-linecap="round"/>"#,
                p[0],
                p[1],
                q[0],
                q[1],
                limb_colour(b)
            );
        }
    }
    if !band {
        for (p, &guessed) in points.iter().zip(filled) {
            let Some(p) = p else { continue };
            let _ = if guessed {
                writeln!(
                    svg,
                    r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="white" stroke="{CENTRE}" stroke-width="1.5"/>"#,
                    p[0], p[1]
                )
            } else {
                writeln!(
                    svg,
                    r#"<circle cx="{:.1}" cy="{:.1}" r="2.5" fill="{CENTRE}"/>"#,
                    p[0], p[1]
                )
            };
        }
    }
}

/// An SVG document of `w` x `h` pixels on a white background, left open for drawing.
fn begin(w: f64, h: f64) -> String {
    begin_above(w, h, 0.0)
}

/// [`begin`] with `above` more pixels on top, at negative y (the drawing's coordinates stay
/// those of a `w` x `h` document).
fn begin_above(w: f64, h: f64, above: f64) -> String {
    let mut svg = String::new();
    let total = h + above;
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{total}" viewBox="0 {} {w} {total}" font-family="sans-serif" font-size="12">"#,
        0.0 - above
    );
    let _ = writeln!(
        svg,
        r#"<rect y="{}" width="{w}" height="{total}" fill="white"/>"#,
        0.0 - above
    );
    svg
}

/// [`begin`] with `title` written at the top left, broken into lines as captions are; each
/// line after the first adds [`CAPTION_LINE_PX`] on top of the drawing.
fn begin_titled(w: f64, h: f64, title: &str) -> String {
    let lines = caption_lines(title, w - 20.0);
    let above = CAPTION_LINE_PX * (lines.len() - 1) as f64;
    let mut svg = begin_above(w, h, above);
    draw_caption(&mut svg, &lines, 10.0, 20.0 - above);
    svg
}

/// Writes `lines` at `x`, the first line's baseline at `y`, each next one
/// [`CAPTION_LINE_PX`] lower.
fn draw_caption(svg: &mut String, lines: &[String], x: f64, y: f64) {
    for (k, line) in lines.iter().enumerate() {
        let _ = writeln!(
            svg,
            r#"<text x="{x}" y="{}" fill="{CENTRE}">{}</text>"#,
            y + CAPTION_LINE_PX * k as f64,
            camloc::store::markup_escaped(line)
        );
    }
}

/// The continuous viewpoint of a localization (docs/conventions.md section 2): the direction
/// from the body to the camera and the angular radius of its uncertainty, degrees.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Direction {
    /// Azimuth, degrees (180 = in front of the body, 270 = its left).
    pub azimuth_deg: f64,
    /// Elevation above the horizontal plane, degrees.
    pub elevation_deg: f64,
    /// Angular radius holding about 68% of the direction errors, degrees.
    pub uncertainty_deg: f64,
}

impl Direction {
    /// The continuous viewpoint of `loc`, when its model predicts one.
    pub fn of(loc: &Localization) -> Option<Direction> {
        Some(Direction {
            azimuth_deg: loc.azimuth_deg?,
            elevation_deg: loc.elevation_deg?,
            uncertainty_deg: loc.uncertainty_deg?,
        })
    }
}

/// A 2D pose (left) and the camera sphere (right) with every camera's probability (a dot's
/// area, and its percentage from [`SHOWN_PROBABILITY`]), the predicted viewpoint ringed and,
/// when known, the continuous direction with its uncertainty.
///
/// `pose` is in image coordinates (v down); missing landmarks are left out. `probabilities`
/// holds each camera's probability (index [`CameraLabel::index`]), `label` is the predicted
/// camera of `cameras`, `caption` text shown under the drawing (broken into as many lines as
/// its width needs; the drawing grows by a line for each).
pub fn localization_svg(
    pose: &PartialPose2,
    cameras: &CameraSet,
    probabilities: &[f64],
    label: CameraLabel,
    direction: Option<Direction>,
    caption: &str,
) -> String {
    let w = 640.0;
    let lines = caption_lines(caption, w - 20.0);
    let h = 360.0 + CAPTION_LINE_PX * (lines.len() - 1) as f64;
    let mut svg = begin(w, h);
    let present: Vec<[f64; 2]> = pose.points.iter().flatten().copied().collect();
    let map = fit_box(&present, 10.0, 10.0, 300.0, 310.0);
    draw_skeleton(
        &mut svg,
        &pose.points.map(|p| p.map(&map)),
        false,
        3.0,
        &[false; 15],
    );
    let sphere = draw_sphere(
        &mut svg,
        cameras,
        (probabilities, label.get()),
        (330.0, 10.0, 300.0, 310.0),
    );
    if let Some(direction) = direction {
        draw_direction(&mut svg, &sphere, direction);
    }
    draw_caption(&mut svg, &lines, 10.0, 346.0);
    let _ = writeln!(
        svg,
        r#"<text x="10" y="22" fill="{LEFT}">left</text><text x="40" y="22" fill="{RIGHT}">right</text>"#
    );
    svg.push_str("</svg>\n");
    svg
}

/// Where [`draw_sphere`] put the sphere: its viewing rotation, centre and radius in the drawing.
struct SphereView {
    view: Matrix3,
    centre: [f64; 2],
    radius: f64,
}

impl SphereView {
    /// Drawing coordinates of a point of the sphere (unit radius) or inside it.
    fn to_svg(&self, p: Vector3) -> [f64; 2] {
        let q = self.view * p;
        [
            self.centre[0] + self.radius * q.x,
            self.centre[1] + self.radius * q.y,
        ]
    }

    /// Whether a point of the sphere lies on its far side, away from the viewer.
    fn is_far(&self, p: Vector3) -> bool {
        (self.view * p).z > 0.0
    }
}

/// The attribute that pales what lies on the far side of the sphere ([`SphereView::is_far`]).
const FAR: &str = r#" opacity="0.45""#;

/// Orange of the continuous direction.
const DIRECTION: &str = "#e6730f";

/// The continuous direction on the sphere: a line from the body to the predicted point, and
/// the uncertainty as the circle of directions at its angular radius around it (shaded).
fn draw_direction(svg: &mut String, sphere: &SphereView, d: Direction) {
    let centre = sphere_point(d.azimuth_deg, d.elevation_deg, 1.0);
    // Two unit vectors across the direction: the azimuth and elevation tangents.
    let across = sphere_point(d.azimuth_deg + 90.0, 0.0, 1.0);
    let up = centre.cross(&across);
    let u = d.uncertainty_deg.clamp(0.0, 180.0).to_radians();
    let mut path = String::new();
    for k in 0..=48 {
        let phi = k as f64 * std::f64::consts::TAU / 48.0;
        let p = centre * u.cos() + (across * phi.cos() + up * phi.sin()) * u.sin();
        let q = sphere.to_svg(p);
        let _ = write!(
            path,
            "{}{:.1},{:.1} ",
            if k == 0 { "M" } else { "L" },
            q[0],
            q[1]
        );
    }
    let _ = writeln!(
        svg,
        r#"<path d="{path}Z" fill="{DIRECTION}" fill-opacity="0.2" stroke="{DIRECTION}" stroke-dasharray="3 2"/>"#
    );
    let (o, p) = (sphere.to_svg(Vector3::zeros()), sphere.to_svg(centre));
    // Paler on the far side of the sphere, as the cameras there are (it would read as the
    // near camera it is drawn over).
    let opacity = if sphere.is_far(centre) { FAR } else { "" };
    let _ = writeln!(
        svg,
        r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{DIRECTION}" stroke-width="2"{opacity}/><circle cx="{:.1}" cy="{:.1}" r="4.5" fill="{DIRECTION}"{opacity}/>"#,
        o[0], o[1], p[0], p[1], p[0], p[1]
    );
    // From the panel's left edge, so that a negative elevation and a two-digit uncertainty
    // stay inside the drawing.
    let _ = writeln!(
        svg,
        r#"<text x="{:.1}" y="{:.1}" fill="{DIRECTION}">direction: azimuth {:.0}, elevation {:.0}, +- {:.0} deg</text>"#,
        sphere.centre[0] - 150.0,
        sphere.centre[1] + sphere.radius + 14.0,
        d.azimuth_deg,
        d.elevation_deg,
        d.uncertainty_deg
    );
}

/// The probability from which a camera's dot on the sphere is labelled with its percentage.
pub const SHOWN_PROBABILITY: f64 = 0.05;

/// The camera sphere seen obliquely in the box `(x, y, w, h)`: rings at each elevation, a
/// small body at the centre facing -x, a dot per camera whose area grows with its probability
/// (`chosen.0`, index [`CameraLabel::index`]) and the camera labelled `chosen.1` red and
/// ringed. Returns where it is.
fn draw_sphere(
    svg: &mut String,
    cameras: &CameraSet,
    chosen: (&[f64], u16),
    (x, y, w, h): (f64, f64, f64, f64),
) -> SphereView {
    let (probabilities, label) = chosen;
    // View the sphere from azimuth 215 deg (front-left), elevation 20 deg.
    let view = match look_at_origin(sphere_point(215.0, 20.0, 1.0)) {
        Ok(r) => r,
        Err(_) => Matrix3::identity(),
    };
    let radius = 0.42 * w.min(h);
    let (cx, cy) = (x + w / 2.0, y + h / 2.0);
    let sphere = SphereView {
        view,
        centre: [cx, cy],
        radius,
    };
    let to_svg = |p: Vector3| sphere.to_svg(p);
    let _ = writeln!(
        svg,
        r##"<circle cx="{cx:.1}" cy="{cy:.1}" r="{radius:.1}" fill="none" stroke="#bbbbbb"/>"##
    );
    for &elevation in cameras.elevations_deg() {
        let mut d = String::new();
        for k in 0..=72 {
            let p = to_svg(sphere_point(k as f64 * 5.0, elevation, 1.0));
            let _ = write!(
                d,
                "{}{:.1},{:.1} ",
                if k == 0 { "M" } else { "L" },
                p[0],
                p[1]
            );
        }
        let _ = writeln!(svg, r##"<path d="{d}" fill="none" stroke="#cccccc"/>"##);
    }
    // A stick body at the centre: feet to head along z, a nose pointing to -x (front).
    let body = [
        (Vector3::new(0.0, 0.0, -0.35), Vector3::new(0.0, 0.0, 0.3)),
        (Vector3::new(0.0, -0.12, 0.2), Vector3::new(0.0, 0.12, 0.2)),
        (Vector3::new(0.0, 0.0, 0.3), Vector3::new(-0.15, 0.0, 0.3)),
    ];
    for (a, b) in body {
        let (p, q) = (to_svg(a), to_svg(b));
        let _ = writeln!(
            svg,
            r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{CENTRE}" stroke-width="2"/>"#,
            p[0], p[1], q[0], q[1]
        );
    }
    for (k, v) in cameras.viewpoints().iter().enumerate() {
        let p = to_svg(v.position(1.0));
        let chosen = v.label == label;
        let probability = probabilities.get(k).copied().filter(|p| p.is_finite());
        // Area in proportion to the probability, from a dot of 3 px for none.
        let r = 3.0 + 7.0 * probability.unwrap_or(0.0).clamp(0.0, 1.0).sqrt();
        let fill = if chosen { RIGHT } else { "#777777" };
        // A camera on the far side of the sphere (away from the viewer) is paler, unless it
        // is the answer or has a share worth reading.
        let faded = sphere.is_far(v.position(1.0))
            && !chosen
            && probability.is_none_or(|p| p < SHOWN_PROBABILITY);
        let opacity = if faded { FAR } else { "" };
        let _ = writeln!(
            svg,
            r#"<circle cx="{:.1}" cy="{:.1}" r="{r:.1}" fill="{fill}"{opacity}/>"#,
            p[0], p[1]
        );
        if chosen {
            // A ring, so that the answer does not hang on telling red from grey.
            let _ = writeln!(
                svg,
                r#"<circle cx="{:.1}" cy="{:.1}" r="{:.1}" fill="none" stroke="{CENTRE}" stroke-width="1.5"/>"#,
                p[0],
                p[1],
                r + 3.0
            );
        }
        if chosen || cameras.len() <= 16 {
            let percent = probability
                .filter(|&p| p >= SHOWN_PROBABILITY)
                .map_or(String::new(), |p| format!(" {:.0}%", 100.0 * p));
            // Beside the dot, on the side towards the sphere's centre when a percentage
            // would run past the drawing's right edge.
            let (x, anchor) = if !percent.is_empty() && p[0] > cx {
                (p[0] - r - 4.0, r#" text-anchor="end""#)
            } else {
                (p[0] + r + 4.0, "")
            };
            let _ = writeln!(
                svg,
                r#"<text x="{x:.1}" y="{:.1}" fill="{fill}"{anchor}{opacity}>{}{percent}</text>"#,
                p[1] - 6.0,
                v.label_text()
            );
        }
    }
    sphere
}

/// Orthographic view of a 3D point (metres) onto drawing coordinates (v down).
type ViewProjection = fn([f64; 3]) -> [f64; 2];

/// The 3D skeleton's views in [`reconstruction_svg`], canonical body frame (facing -x, its
/// right towards +y, z up): from the front and from the left side as Table-1 cameras 05 and
/// 06 see it (right = the camera's x axis, down = its y axis), and from above with the front
/// up, so that the person's right is on the right.
const SKELETON_VIEWS: [(&str, ViewProjection); 3] = [
    ("front", |p| [-p[1], -p[2]]),
    ("left side", |p| [p[0], -p[2]]),
    ("top", |p| [p[1], p[0]]),
];

/// Input 2D pose (a pale band; its missing landmarks left out) with the reprojection of the
/// reconstruction over it, and the 3D skeleton from the front (camera on -x), the left side
/// (-y) and above (+z), `caption` under them (broken into lines as
/// [`localization_svg`]'s).
pub fn reconstruction_svg(
    input: &PartialPose2,
    reprojection: &Pose2,
    pose: &Pose3,
    caption: &str,
) -> String {
    let w = 880.0;
    let lines = caption_lines(caption, w - 20.0);
    let h = 260.0 + CAPTION_LINE_PX * (lines.len() - 1) as f64;
    let mut svg = begin(w, h);
    let both: Vec<[f64; 2]> = input
        .points
        .iter()
        .flatten()
        .chain(&reprojection.points)
        .copied()
        .collect();
    let map = fit_box(&both, 10.0, 20.0, 200.0, 210.0);
    let filled = input.points.map(|p| p.is_none());
    draw_skeleton(
        &mut svg,
        &input.points.map(|p| p.map(&map)),
        true,
        2.0,
        &filled,
    );
    draw_skeleton(
        &mut svg,
        &reprojection.points.map(|p| Some(map(p))),
        false,
        2.0,
        &filled,
    );
    let _ = writeln!(
        svg,
        r#"<text x="20" y="16">input (pale band) and reprojection (thin)</text>"#
    );
    if filled.contains(&true) {
        let _ = writeln!(
            svg,
            r#"<text x="20" y="31" font-size="11">hollow rings: joints filled in, not measured</text>"#
        );
    }
    // One scale for the three views so that they compare; each view centred on its points.
    let views = &SKELETON_VIEWS;
    let span = views
        .iter()
        .flat_map(|(_, f)| {
            let q: Vec<[f64; 2]> = pose.points.iter().map(|p| f(*p)).collect();
            (0..2).map(move |k| {
                let (lo, hi) = q
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p[k]), hi.max(p[k]))
                    });
                hi - lo
            })
        })
        .fold(1e-12, f64::max);
    let scale = 0.9 * 200.0 / span;
    for (k, (name, f)) in views.iter().enumerate() {
        let x0 = 230.0 + 215.0 * k as f64;
        let projected: Vec<[f64; 2]> = pose.points.iter().map(|p| f(*p)).collect();
        // Centred on its bounding box (its points' mean had put a long arm of an LSP photo
        // past the panel's edge; the box fits the span the scale was made for).
        let c = [0, 1].map(|k| {
            let (lo, hi) = (projected.iter())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p[k]), b.max(p[k]))
                });
            0.5 * (lo + hi)
        });
        let mut pts = [None; 15];
        for (o, p) in pts.iter_mut().zip(&projected) {
            *o = Some([
                x0 + 100.0 + scale * (p[0] - c[0]),
                125.0 + scale * (p[1] - c[1]),
            ]);
        }
        draw_skeleton(&mut svg, &pts, false, 2.0, &filled);
        let _ = writeln!(
            svg,
            r#"<text x="{:.1}" y="16">3D, {name}</text>"#,
            x0 + 60.0
        );
    }
    draw_caption(&mut svg, &lines, 10.0, 252.0);
    svg.push_str("</svg>\n");
    svg
}

/// A timeline of one person's viewpoint: frames on x (in sequence order, evenly spaced: gaps
/// in the frame numbers are not drawn; the axis names the first and last frame numbers,
/// `frame_range`), the cameras of `cameras` on y (label 1 at the top), a grey tick per frame
/// at its raw (per-frame) camera (none for a frame that was not localized) and the smoothed
/// camera as a red step line.
pub fn timeline_svg(
    cameras: &CameraSet,
    raw: &[Option<CameraLabel>],
    smoothed: &[SmoothedFrame],
    frame_range: [u64; 2],
    title: &str,
) -> String {
    let (left, top, plot_w, row_h) = (110.0, 40.0, 900.0, 22.0);
    let k = cameras.len().max(1);
    let n = raw.len().max(smoothed.len()).max(1);
    let (w, h) = (left + plot_w + 20.0, top + row_h * k as f64 + 50.0);
    let dx = plot_w / n as f64;
    let x_at = |t: usize| left + dx * t as f64;
    // Rings from the upper one at the top down to the lower one, as the cameras stand.
    let (azimuths, rings) = (cameras.azimuths().max(1), cameras.elevations_deg().len());
    let y_at = |index: usize| {
        let row = (rings.saturating_sub(1 + index / azimuths)) * azimuths + index % azimuths;
        top + row_h * (row as f64 + 0.5)
    };
    let mut svg = begin_titled(w, h, title);
    let repeat = cameras.names_repeat();
    for v in cameras.viewpoints() {
        let y = y_at(usize::from(v.label.saturating_sub(1)));
        let _ = writeln!(
            svg,
            r##"<line x1="{left}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="#eeeeee"/><text x="10" y="{:.1}" fill="{CENTRE}">{}</text>"##,
            left + plot_w,
            y + 4.0,
            row_name(v, repeat)
        );
    }
    // Raw labels: one short horizontal tick per frame, all in one path.
    let tick = dx.max(1.0);
    let mut d = String::new();
    for (t, label) in raw.iter().enumerate() {
        if let Some(label) = label {
            let _ = write!(d, "M{:.1},{:.1}h{tick:.1}", x_at(t), y_at(label.index()));
        }
    }
    let _ = writeln!(
        svg,
        r##"<path d="{d}" stroke="#999999" stroke-width="6" fill="none"/>"##
    );
    // Smoothed labels: a step line with a point only where the camera changes.
    let mut d = String::new();
    let mut previous = None;
    for (t, s) in smoothed.iter().enumerate() {
        let y = y_at(s.label.index());
        match previous {
            None => {
                let _ = write!(d, "M{:.1},{y:.1}", x_at(t));
            }
            Some(p) if p != y => {
                let _ = write!(d, "H{:.1}V{y:.1}", x_at(t));
            }
            _ => {}
        }
        previous = Some(y);
    }
    if previous.is_some() {
        let _ = write!(d, "H{:.1}", x_at(smoothed.len()));
    }
    let _ = writeln!(
        svg,
        r##"<path d="{d}" stroke="{RIGHT}" stroke-width="2" fill="none"/>"##
    );
    let bottom = top + row_h * k as f64;
    let _ = writeln!(
        svg,
        r##"<text x="{left}" y="{:.1}" fill="{CENTRE}">frame {}</text><text x="{:.1}" y="{:.1}" fill="{CENTRE}" text-anchor="end">frame {}</text>"##,
        bottom + 18.0,
        frame_range[0],
        left + plot_w,
        bottom + 18.0,
        frame_range[1]
    );
    let _ = writeln!(
        svg,
        r##"<text x="{left}" y="{:.1}" fill="#999999">per frame</text><text x="{:.1}" y="{:.1}" fill="{RIGHT}">smoothed</text>"##,
        bottom + 38.0,
        left + 80.0,
        bottom + 38.0
    );
    svg.push_str("</svg>\n");
    svg
}

/// Fill colour of a cell whose share is `fraction` (0 white to 1 dark blue).
fn shade(fraction: f64) -> String {
    let f = if fraction.is_finite() {
        fraction.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let channel = |white: f64, dark: f64| (white + (dark - white) * f).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        channel(255.0, 8.0),
        channel(255.0, 48.0),
        channel(255.0, 107.0)
    )
}

/// Text colour readable on a cell of share `fraction`.
fn ink(fraction: f64) -> &'static str {
    if fraction > 0.55 { "white" } else { CENTRE }
}

/// A camera as a drawing's row names it: `05 middle front`, or, when the set's level and
/// side names `repeat` ([`CameraSet::names_repeat`]), by its angles: `02 az 225, el -20`.
fn row_name(v: &Viewpoint, repeat: bool) -> String {
    if repeat {
        format!("{} {}", v.label_text(), v.angles_text())
    } else {
        format!("{} {} {}", v.label_text(), v.level.name(), v.side.name())
    }
}

/// The confusion matrix of an evaluation: `confusion[t][p]` samples of true camera index `t`
/// predicted as `p`, rows labelled with the true camera, columns with the predicted one, each
/// cell shaded by its share of the row and showing its count.
pub fn confusion_svg(cameras: &CameraSet, confusion: &[Vec<usize>], title: &str) -> String {
    let k = confusion.len();
    let (left, top, cell) = (130.0, 70.0, 40.0);
    let (w, h) = (left + cell * k as f64 + 20.0, top + cell * k as f64 + 40.0);
    let mut svg = begin_titled(w, h, title);
    let _ = writeln!(
        svg,
        r#"<text x="{left}" y="45" fill="{CENTRE}">predicted camera</text><text x="10" y="{:.1}" fill="{CENTRE}">true camera</text>"#,
        top - 8.0
    );
    let repeat = cameras.names_repeat();
    let name = |index: usize| {
        (cameras.viewpoints().get(index))
            .map_or_else(|| format!("{:02}", index + 1), |v| row_name(v, repeat))
    };
    for (t, row) in confusion.iter().enumerate() {
        let y = top + cell * t as f64;
        let total: usize = row.iter().sum();
        let _ = writeln!(
            svg,
            r#"<text x="10" y="{:.1}" fill="{CENTRE}">{}</text>"#,
            y + cell / 2.0 + 4.0,
            name(t)
        );
        for (p, &count) in row.iter().enumerate() {
            let x = left + cell * p as f64;
            let share = if total > 0 {
                count as f64 / total as f64
            } else {
                0.0
            };
            let _ = writeln!(
                svg,
                r##"<rect x="{x:.1}" y="{y:.1}" width="{cell}" height="{cell}" fill="{}" stroke="#dddddd"/><text x="{:.1}" y="{:.1}" fill="{}" font-size="10" text-anchor="middle">{count}</text>"##,
                shade(share),
                x + cell / 2.0,
                y + cell / 2.0 + 4.0,
                ink(share)
            );
        }
    }
    for p in 0..k {
        let _ = writeln!(
            svg,
            r#"<text x="{:.1}" y="{:.1}" fill="{CENTRE}" text-anchor="middle">{:02}</text>"#,
            left + cell * (p as f64 + 0.5),
            top - 8.0,
            p + 1
        );
    }
    let _ = writeln!(
        svg,
        r#"<text x="10" y="{:.1}" fill="{CENTRE}">cells: sample counts, shaded by share of the row</text>"#,
        h - 12.0
    );
    svg.push_str("</svg>\n");
    svg
}

/// Where the cameras of a whole input fall: the cameras as a grid of azimuth (columns, in
/// label order from the front) by elevation (rows, highest at the top), each cell shaded by
/// its share of the poses and showing its count; `counts[i]` is the number of poses whose
/// camera has index `i`.
pub fn summary_svg(cameras: &CameraSet, counts: &[u64], title: &str) -> String {
    let azimuths = cameras.azimuths().max(1);
    let rings = cameras.elevations_deg().len().max(1);
    let (left, top, cw, ch) = (120.0, 50.0, 110.0, 60.0);
    let (w, h) = (
        left + cw * azimuths as f64 + 20.0,
        top + ch * rings as f64 + 50.0,
    );
    let total: u64 = counts.iter().sum();
    let mut svg = begin_titled(w, h, title);
    for v in cameras.viewpoints() {
        let index = usize::from(v.label.saturating_sub(1));
        let (ring, az) = (index / azimuths, index % azimuths);
        let (x, y) = (left + cw * az as f64, top + ch * (rings - 1 - ring) as f64);
        let count = counts.get(index).copied().unwrap_or(0);
        let share = if total > 0 {
            count as f64 / total as f64
        } else {
            0.0
        };
        let _ = writeln!(
            svg,
            r##"<rect x="{x:.1}" y="{y:.1}" width="{cw}" height="{ch}" fill="{}" stroke="#dddddd"/><text x="{:.1}" y="{:.1}" fill="{ink}" text-anchor="middle">camera {}</text><text x="{:.1}" y="{:.1}" fill="{ink}" text-anchor="middle">{count} ({:.1}%)</text>"##,
            shade(share),
            x + cw / 2.0,
            y + 24.0,
            v.label_text(),
            x + cw / 2.0,
            y + 42.0,
            100.0 * share,
            ink = ink(share)
        );
        if ring == 0 {
            let _ = writeln!(
                svg,
                r#"<text x="{:.1}" y="{:.1}" fill="{CENTRE}" text-anchor="middle">{} ({:.0} deg)</text>"#,
                x + cw / 2.0,
                top + ch * rings as f64 + 18.0,
                v.side.name(),
                v.azimuth_deg
            );
        }
        if az == 0 {
            let _ = writeln!(
                svg,
                r#"<text x="10" y="{:.1}" fill="{CENTRE}">{} ({:+.0} deg)</text>"#,
                y + ch / 2.0 + 4.0,
                v.level.name(),
                v.elevation_deg
            );
        }
    }
    let _ = writeln!(
        svg,
        r#"<text x="10" y="{:.1}" fill="{CENTRE}">{total} poses; azimuth by elevation, shaded by share</text>"#,
        h - 10.0
    );
    svg.push_str("</svg>\n");
    svg
}

#[cfg(test)]
mod tests;
