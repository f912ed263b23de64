//! An SVG picture of a grasp: the object's triangles and the hand's capsules, seen from the side
//! and from the fingertips in the hook's frame, drawn back to front. Written by hand because it is
//! a few dozen lines of text output and no SVG crate draws depth-sorted meshes.

use std::fmt::Write as _;

use prehensile_core::math::{Point3, Rotation, Vec3};
use prehensile_core::search::GraspResult;
use prehensile_core::ObjectModel;

const PANEL: f64 = 480.0;
const FINGER_COLOURS: [&str; 8] = [
    "#d1495b", "#edae49", "#00798c", "#30638e", "#66a182", "#8d6cab", "#e07a5f", "#3d405b",
];

/// Two side-by-side views of the grasp as an SVG document.
pub fn grasp_svg(object: &ObjectModel, result: &GraspResult) -> String {
    let q = result.hook_rotation_xyzw;
    let hook = Rotation::from_quaternion(nalgebra::Quaternion::new(q[3], q[0], q[1], q[2]));
    let (x, y, z) = (hook * Vec3::x(), hook * Vec3::y(), hook * Vec3::z());
    // Screen right, screen up, toward the viewer. The palm faces +y, so −y is up on screen.
    let views = [("side", z, -y, x), ("along the fingers", x, -y, -z)];
    let mut fingers: Vec<&str> = Vec::new();
    for c in &result.capsules {
        if !fingers.contains(&c.finger.as_str()) {
            fingers.push(&c.finger);
        }
    }
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" font-size=\"13\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        2.0 * PANEL,
        PANEL + 40.0
    );
    for (k, (label, right, up, toward)) in views.iter().enumerate() {
        let _ = write!(svg, "<g transform=\"translate({},0)\">", k as f64 * PANEL);
        draw_view(&mut svg, object, result, (*right, *up, *toward), &fingers);
        let _ = writeln!(svg, "<text x=\"10\" y=\"20\">{label}</text></g>");
    }
    let mut legend_x = 10.0;
    for (i, f) in fingers.iter().enumerate() {
        let colour = FINGER_COLOURS[i % FINGER_COLOURS.len()];
        let _ = write!(
            svg,
            "<rect x=\"{legend_x}\" y=\"{}\" width=\"12\" height=\"12\" fill=\"{colour}\"/><text x=\"{}\" y=\"{}\">{f}</text>",
            PANEL + 14.0,
            legend_x + 16.0,
            PANEL + 25.0
        );
        legend_x += 20.0 + 8.0 * f.len() as f64;
    }
    let _ = write!(
        svg,
        "<text x=\"{}\" y=\"{}\">{} on {}: {} grasp, {}</text>\n</svg>\n",
        legend_x + 10.0,
        PANEL + 25.0,
        result.hand,
        result.object,
        result.movement,
        if result.valid { "valid" } else { "not valid" }
    );
    svg
}

fn draw_view(
    svg: &mut String,
    object: &ObjectModel,
    result: &GraspResult,
    (right, up, toward): (Vec3, Vec3, Vec3),
    fingers: &[&str],
) {
    let project = |p: &Point3| {
        (
            p.coords.dot(&right),
            p.coords.dot(&up),
            p.coords.dot(&toward),
        )
    };
    // Fit everything into the panel.
    let mut points: Vec<(f64, f64, f64)> = object.mesh().vertices.iter().map(project).collect();
    for c in &result.capsules {
        for e in [c.a, c.b] {
            let (u, v, w) = project(&Point3::from(e));
            points.push((u - c.radius, v - c.radius, w));
            points.push((u + c.radius, v + c.radius, w));
        }
    }
    let (mut lo_u, mut hi_u, mut lo_v, mut hi_v) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (u, v, _) in &points {
        lo_u = lo_u.min(*u);
        hi_u = hi_u.max(*u);
        lo_v = lo_v.min(*v);
        hi_v = hi_v.max(*v);
    }
    let scale = (PANEL - 40.0) / (hi_u - lo_u).max(hi_v - lo_v).max(1e-9);
    let sx = |u: f64| 20.0 + (u - lo_u) * scale;
    let sy = |v: f64| PANEL - 20.0 - (v - lo_v) * scale;
    let mut items: Vec<(f64, String)> = Vec::new();
    let light = (toward * 0.8 + up * 0.6).normalize();
    for t in 0..object.mesh().triangles.len() {
        let [a, b, c] = object.mesh().corners(t);
        let n = (b - a).cross(&(c - a));
        if n.dot(&toward) <= 0.0 {
            continue;
        }
        let shade = 90.0 + 140.0 * n.normalize().dot(&light).max(0.0);
        let (pa, pb, pc) = (project(&a), project(&b), project(&c));
        let grey = shade as u8;
        items.push((
            (pa.2 + pb.2 + pc.2) / 3.0,
            format!(
                "<polygon points=\"{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}\" fill=\"rgb({grey},{grey},{grey})\" stroke=\"rgb({grey},{grey},{grey})\" stroke-width=\"0.5\"/>",
                sx(pa.0), sy(pa.1), sx(pb.0), sy(pb.1), sx(pc.0), sy(pc.1)
            ),
        ));
    }
    for c in &result.capsules {
        let (pa, pb) = (project(&Point3::from(c.a)), project(&Point3::from(c.b)));
        let i = fingers.iter().position(|f| *f == c.finger).unwrap_or(0);
        let colour = FINGER_COLOURS[i % FINGER_COLOURS.len()];
        let width = 2.0 * c.radius * scale;
        let line = |stroke: &str, w: f64| {
            format!(
                "<line x1=\"{:.1}\" y1=\"{:.1}\" x2=\"{:.1}\" y2=\"{:.1}\" stroke=\"{stroke}\" stroke-width=\"{w:.1}\" stroke-linecap=\"round\" opacity=\"0.92\"/>",
                sx(pa.0), sy(pa.1), sx(pb.0), sy(pb.1)
            )
        };
        let outline = if c.touching { "#111" } else { "#666" };
        items.push((
            (pa.2 + pb.2) / 2.0,
            line(outline, width + 2.0) + &line(colour, width),
        ));
    }
    items.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (_, s) in items {
        svg.push_str(&s);
        svg.push('\n');
    }
}
