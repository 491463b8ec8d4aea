//! SVG drawings: a 2D skeleton with its predicted viewpoint on a sphere diagram, and a
//! reconstruction (input, reprojection, three views of the 3D skeleton).

use std::fmt::Write;

use camloc::geometry::{CameraLabel, CameraSet, Matrix3, Vector3, look_at_origin, sphere_point};
use camloc::skeleton::{LIMBS, Landmark, PartialPose2, Pose2, Pose3};

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

/// Draws the limbs of a (possibly partial) 2D pose already mapped to SVG coordinates.
fn draw_skeleton(svg: &mut String, points: &[Option<[f64; 2]>; 15], dashed: bool, width: f64) {
    for (a, b) in LIMBS {
        if let (Some(p), Some(q)) = (points[a.index()], points[b.index()]) {
            let dash = if dashed {
                r#" stroke-dasharray="4 3""#
            } else {
                ""
            };
            let _ = writeln!(
                svg,
                r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{}" stroke-width="{width}" stroke-linecap="round"{dash}/>"#,
                p[0],
                p[1],
                q[0],
                q[1],
                limb_colour(b)
            );
        }
    }
    if !dashed {
        for p in points.iter().flatten() {
            let _ = writeln!(
                svg,
                r#"<circle cx="{:.1}" cy="{:.1}" r="2.5" fill="{CENTRE}"/>"#,
                p[0], p[1]
            );
        }
    }
}

/// An SVG document of `w` x `h` pixels on a white background, left open for drawing.
fn begin(w: f64, h: f64) -> String {
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(svg, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    svg
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// A 2D pose (left) and the camera sphere (right) with the predicted viewpoint highlighted.
///
/// `pose` is in image coordinates (v down); missing landmarks are left out. `label` is the
/// predicted camera of `cameras`, `caption` a line of text shown under the drawing.
pub fn localization_svg(
    pose: &PartialPose2,
    cameras: &CameraSet,
    label: CameraLabel,
    caption: &str,
) -> String {
    let (w, h) = (640.0, 360.0);
    let mut svg = begin(w, h);
    let present: Vec<[f64; 2]> = pose.points.iter().flatten().copied().collect();
    let map = fit_box(&present, 10.0, 10.0, 300.0, 310.0);
    draw_skeleton(&mut svg, &pose.points.map(|p| p.map(&map)), false, 3.0);
    draw_sphere(&mut svg, cameras, label.get(), 330.0, 10.0, 300.0, 310.0);
    let _ = writeln!(
        svg,
        r#"<text x="10" y="{}" fill="{CENTRE}">{}</text>"#,
        h - 14.0,
        escape(caption)
    );
    let _ = writeln!(
        svg,
        r#"<text x="10" y="22" fill="{LEFT}">left</text><text x="40" y="22" fill="{RIGHT}">right</text>"#
    );
    svg.push_str("</svg>\n");
    svg
}

/// The camera sphere seen obliquely: rings at each elevation, a small body at the centre
/// facing -x, a dot per camera and the `label` camera highlighted.
fn draw_sphere(svg: &mut String, cameras: &CameraSet, label: u16, x: f64, y: f64, w: f64, h: f64) {
    // View the sphere from azimuth 215 deg (front-left), elevation 20 deg.
    let view = match look_at_origin(sphere_point(215.0, 20.0, 1.0)) {
        Ok(r) => r,
        Err(_) => Matrix3::identity(),
    };
    let radius = 0.42 * w.min(h);
    let (cx, cy) = (x + w / 2.0, y + h / 2.0);
    let to_svg = |p: Vector3| {
        let q = view * p;
        [cx + radius * q.x, cy + radius * q.y]
    };
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
    for v in cameras.viewpoints() {
        let p = to_svg(v.position(1.0));
        let chosen = v.label == label;
        let (r, fill) = if chosen {
            (7.0, RIGHT)
        } else {
            (3.5, "#888888")
        };
        let _ = writeln!(
            svg,
            r#"<circle cx="{:.1}" cy="{:.1}" r="{r}" fill="{fill}"/>"#,
            p[0], p[1]
        );
        if chosen || cameras.len() <= 16 {
            let _ = writeln!(
                svg,
                r#"<text x="{:.1}" y="{:.1}" fill="{fill}">{}</text>"#,
                p[0] + 8.0,
                p[1] - 6.0,
                v.label_text()
            );
        }
    }
}

/// Orthographic view of a 3D point (metres) onto drawing coordinates (v down).
type ViewProjection = fn([f64; 3]) -> [f64; 2];

/// Input 2D pose (dashed) with the reprojection of the reconstruction over it, and the 3D
/// skeleton from the front (camera on -x), the left side (-y) and above (+z).
pub fn reconstruction_svg(
    input: &Pose2,
    reprojection: &Pose2,
    pose: &Pose3,
    caption: &str,
) -> String {
    let (w, h) = (880.0, 260.0);
    let mut svg = begin(w, h);
    let both: Vec<[f64; 2]> = input
        .points
        .iter()
        .chain(&reprojection.points)
        .copied()
        .collect();
    let map = fit_box(&both, 10.0, 20.0, 200.0, 210.0);
    draw_skeleton(&mut svg, &input.points.map(|p| Some(map(p))), true, 2.0);
    draw_skeleton(
        &mut svg,
        &reprojection.points.map(|p| Some(map(p))),
        false,
        2.0,
    );
    let _ = writeln!(
        svg,
        r#"<text x="20" y="16">input (dashed) and reprojection</text>"#
    );
    let views: [(&str, ViewProjection); 3] = [
        ("front", |p| [-p[1], -p[2]]),
        ("left side", |p| [-p[0], -p[2]]),
        ("top", |p| [-p[1], p[0]]),
    ];
    // One scale for the three views so that they compare; each view centred on its points.
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
        let n = projected.len() as f64;
        let c = projected
            .iter()
            .fold([0.0; 2], |a, p| [a[0] + p[0] / n, a[1] + p[1] / n]);
        let mut pts = [None; 15];
        for (o, p) in pts.iter_mut().zip(&projected) {
            *o = Some([
                x0 + 100.0 + scale * (p[0] - c[0]),
                125.0 + scale * (p[1] - c[1]),
            ]);
        }
        draw_skeleton(&mut svg, &pts, false, 2.0);
        let _ = writeln!(
            svg,
            r#"<text x="{:.1}" y="16">3D, {name}</text>"#,
            x0 + 60.0
        );
    }
    let _ = writeln!(
        svg,
        r#"<text x="10" y="{}" fill="{CENTRE}">{}</text>"#,
        h - 8.0,
        escape(caption)
    );
    svg.push_str("</svg>\n");
    svg
}
