//! What every imported hand needs beyond its file: finger names, a hand frame in our convention,
//! radii and fingertips where the file has none.

use prehensile_core::hand::movement::GraspMovement;
use prehensile_core::hand::{BonePart, HandParts};
use prehensile_core::math::{Point3, Rotation, Transform, Vec3};
use prehensile_core::HandModel;

use crate::FormatError;

/// Density used to guess a capsule's radius from a link's mass and length (water, kg/m³).
pub const DENSITY: f64 = 1000.0;

/// A capsule radius from mass and length, as if the link were a cylinder of water, clamped to
/// 2–20 mm.
pub fn radius_from_mass(mass: f64, length: f64) -> f64 {
    if !(mass > 0.0 && length > 0.0) {
        return 0.008;
    }
    (mass / (DENSITY * std::f64::consts::PI * length))
        .sqrt()
        .clamp(0.002, 0.02)
}

/// A human finger name recognised in a bone's name (`thumb`/`th`, `index`/`ff`, `middle`/`mf`,
/// `ring`/`rf`, `little`/`pinky`/`lf`), after any `prefix:`.
pub fn finger_name(bone: &str) -> Option<&'static str> {
    let base = bone.rsplit(':').next().unwrap_or(bone).to_ascii_lowercase();
    let table: [(&[&str], &str); 5] = [
        (&["thumb", "th"], "thumb"),
        (&["index", "ff"], "index"),
        (&["middle", "mf"], "middle"),
        (&["ring", "rf"], "ring"),
        (&["little", "pinky", "lf"], "little"),
    ];
    table
        .iter()
        .find(|(keys, _)| keys.iter().any(|k| base.starts_with(k)))
        .map(|(_, name)| *name)
}

/// Names the finger each chain from the root starts: the first finger name found among the
/// chain's bones (see [`finger_name`]), following each bone's first child.
pub fn name_fingers(parts: &mut HandParts) {
    let Some(root) = parts.bones.iter().find(|b| b.parent.is_none()) else {
        return;
    };
    let root = root.name.clone();
    // Each bone's first child, indexed once: a crafted chain of thousands of bones stays linear.
    let mut first_child: std::collections::HashMap<&str, usize> = Default::default();
    for (k, b) in parts.bones.iter().enumerate() {
        if let Some(p) = &b.parent {
            first_child.entry(p.as_str()).or_insert(k);
        }
    }
    let fingers: Vec<(usize, Option<&str>)> = (0..parts.bones.len())
        .filter(|&i| parts.bones[i].parent.as_deref() == Some(root.as_str()))
        .map(|i| {
            let mut at = Some(i);
            let mut finger = None;
            // A chain visits each bone at most once: names are unique, parents form a tree.
            for _ in 0..parts.bones.len() {
                let Some(k) = at else { break };
                finger = finger_name(&parts.bones[k].name);
                if finger.is_some() {
                    break;
                }
                at = first_child.get(parts.bones[k].name.as_str()).copied();
            }
            (i, finger)
        })
        .collect();
    for (i, finger) in fingers {
        parts.bones[i].finger = finger.map(str::to_string);
    }
}

/// The end of `capsules` farthest from the bone's origin: a fingertip where the file gives none.
pub fn farthest_capsule_end(capsules: &[(Point3, Point3, f64)]) -> Option<Point3> {
    capsules
        .iter()
        .flat_map(|c| [c.0, c.1])
        .max_by(|a, b| a.coords.norm().total_cmp(&b.coords.norm()))
}

/// Overrides for what importing derives, read from a TOML sidecar `<stem>.prehensile.toml`
/// beside the hand file (see docs/HAND_FORMAT.md).
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sidecar {
    /// First bone of a chain -> finger name.
    #[serde(default)]
    pub fingers: std::collections::BTreeMap<String, String>,
    /// Last bone of a finger -> fingertip in that bone's frame, metres.
    #[serde(default)]
    pub tips: std::collections::BTreeMap<String, [f64; 3]>,
    /// Joint (degree of freedom) name -> end angle of the `close` movement, radians. When given,
    /// replaces the derived `close` targets.
    #[serde(default)]
    pub close: std::collections::BTreeMap<String, f64>,
    /// Movement name (`power`, `precision` or a new one) -> what to change in it or give it.
    #[serde(default)]
    pub movements: std::collections::BTreeMap<String, MovementOverride>,
    /// The hand frame, instead of the derived one.
    pub frame: Option<FrameOverride>,
}

/// A sidecar's `[frame]`: the hand frame's axes in the file's palm frame (what `hands --json`
/// shows as `frame`), for a hand whose fingers or closing direction mislead the derivation.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameOverride {
    /// z: along the fingers.
    pub fingers_along: [f64; 3],
    /// y: out of the palm, the side the fingers close toward (made square to z).
    pub palm_normal: [f64; 3],
}

impl FrameOverride {
    /// Unit z and y, y made square to z.
    fn axes(&self, source: &str) -> Result<(Vec3, Vec3), FormatError> {
        let err = |what: &str| FormatError::new(source, format!("the sidecar's [frame] {what}"));
        let (z, y) = (Vec3::from(self.fingers_along), Vec3::from(self.palm_normal));
        if !(z.iter().chain(y.iter()).all(|v| v.is_finite()) && z.norm() > 1e-9) {
            return Err(err("needs a finite, non-zero fingers_along"));
        }
        let z = z.normalize();
        let across = y - z * y.dot(&z);
        if across.norm() <= 1e-6 * y.norm() || across.norm() < 1e-12 {
            return Err(err(
                "has a palm_normal along fingers_along (or zero); give one across the fingers",
            ));
        }
        Ok((z, across.normalize()))
    }
}

/// A sidecar's `[movements.NAME]`: the end angles of named joints (the others keep the derived
/// movement's end, or the open pose for a new movement), the grasp centre and the fingers that
/// must touch.
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MovementOverride {
    /// Joint (degree of freedom) name -> end angle, radians.
    #[serde(default)]
    pub end: std::collections::BTreeMap<String, f64>,
    /// Grasp centre in the hand frame (as `hands --json` shows it), metres.
    pub grasp_center: Option<[f64; 3]>,
    /// Fingers that must touch for the grasp to count (finger names).
    pub contact_fingers: Option<Vec<String>>,
}

impl MovementOverride {
    /// Applies this override to movement `name` of `hand`.
    fn apply(&self, hand: &mut HandModel, name: &str, source: &str) -> Result<(), FormatError> {
        let err = |what: String| {
            FormatError::new(source, format!("the sidecar's [movements.{name}] {what}"))
        };
        let existing = hand.movement(name);
        let mut end =
            existing.map_or_else(|| vec![0.0; hand.dof_count()], |m| m.end_angles().to_vec());
        let limits = hand.dof_limits();
        for (joint, angle) in &self.end {
            let k = hand
                .dof_names()
                .iter()
                .position(|d| d == joint)
                .ok_or_else(|| {
                    err(format!(
                        "names joint '{joint}', which the hand does not have"
                    ))
                })?;
            let [lo, hi] = limits[k];
            if !(angle.is_finite() && (lo - 1e-9..=hi + 1e-9).contains(angle)) {
                return Err(err(format!(
                    "gives joint '{joint}' the end angle {angle}, outside its limits [{lo}, {hi}] (radians)"
                )));
            }
            end[k] = *angle;
        }
        let center = match (self.grasp_center, existing) {
            (Some(c), _) if c.iter().all(|v| v.is_finite()) => Point3::from(c),
            (Some(c), _) => {
                return Err(err(format!("has a grasp_center {c:?} that is not finite")))
            }
            (None, Some(m)) => m.grasp_center(),
            (None, None) => return Err(err("adds a movement without a grasp_center".to_string())),
        };
        let fingers = match (&self.contact_fingers, existing) {
            (Some(names), _) => names
                .iter()
                .map(|f| {
                    hand.fingers().iter().position(|g| &g.name == f).ok_or_else(|| {
                        err(format!("names finger '{f}' in contact_fingers, which the hand does not have"))
                    })
                })
                .collect::<Result<Vec<usize>, FormatError>>()?,
            (None, Some(m)) => m.contact_fingers().to_vec(),
            (None, None) => Vec::new(),
        };
        let mut movement = GraspMovement::to_end_pose(hand, name, end, center, fingers);
        // A derived movement's detour (the power thumb's swing out of the palm) is kept.
        if let Some((fraction, detour)) = existing.and_then(GraspMovement::via_detour) {
            movement = movement
                .through(hand, fraction, &detour)
                .map_err(|e| err(e.to_string()))?;
        }
        hand.set_movement(movement);
        Ok(())
    }
}

impl Sidecar {
    /// The sidecar beside `hand_file`, if there is one.
    pub fn beside(hand_file: &std::path::Path) -> Result<Option<Self>, FormatError> {
        let stem = hand_file
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let path = hand_file.with_file_name(format!("{stem}.prehensile.toml"));
        if !path.exists() {
            return Ok(None);
        }
        let name = path.display().to_string();
        let text = crate::read_input_text(&path, crate::MAX_TEXT_BYTES)?;
        toml::from_str(&text)
            .map(Some)
            .map_err(|e| FormatError::new(&name, e.message().to_string()))
    }

    /// Applies finger names and tips to the parts; `close` is applied after the frame is built.
    fn apply(&self, parts: &mut HandParts, source: &str) -> Result<(), FormatError> {
        for (bone, finger) in &self.fingers {
            let b = parts.bones.iter_mut().find(|b| &b.name == bone).ok_or_else(|| {
                FormatError::new(source, format!("the sidecar names bone '{bone}' in [fingers], which the hand does not have"))
            })?;
            b.finger = Some(finger.clone());
        }
        for (bone, tip) in &self.tips {
            let b = parts.bones.iter_mut().find(|b| &b.name == bone).ok_or_else(|| {
                FormatError::new(source, format!("the sidecar names bone '{bone}' in [tips], which the hand does not have"))
            })?;
            b.tip = Some(Point3::from(*tip));
        }
        Ok(())
    }
}

/// Builds the model, then re-expresses it in our hand frame: z along the mean direction from the
/// root to the fingertips, y toward where the generic close movement moves them (out of the
/// palm). Source joint axes, names and angles are kept; only the root's rest frame turns.
pub fn build_in_hand_frame(
    mut parts: HandParts,
    source: &str,
    sidecar: Option<&Sidecar>,
) -> Result<HandModel, FormatError> {
    let err = |e: prehensile_core::HandError| FormatError::caused_by(source, e);
    if let Some(s) = sidecar {
        s.apply(&mut parts, source)?;
    }
    // First estimate of the palm side: move only each finger's last hinge, almost always a
    // flexion, toward its larger limit (the last one no coupling derives from another).
    let plain = HandModel::from_parts(parts.clone()).map_err(err)?;
    let followers: Vec<String> = parts.couplings.iter().map(|c| c.0.clone()).collect();
    let mut first_pass = Vec::new();
    for finger in plain.fingers() {
        for &b in finger.bones.iter().rev() {
            let bone = &plain.bones()[b];
            let name = &plain.dof_names()[bone.first_dof..bone.first_dof + bone.joint.dofs()];
            if let (prehensile_core::hand::Joint::Hinge(axis), [name]) = (&bone.joint, name) {
                if !followers.contains(name) {
                    let [lo, hi] = axis.limits;
                    first_pass.push((name.clone(), if hi.abs() >= lo.abs() { hi } else { lo }));
                    break;
                }
            }
        }
    }
    parts.close = first_pass;
    let model = HandModel::from_parts(parts.clone()).map_err(err)?;
    let close = model.movement("close").expect("every hand has close");
    let tips = |f: f64| -> Vec<Point3> {
        let rotations: Vec<Rotation> = (0..model.bones().len())
            .map(|b| close.rotation_at(b, f))
            .collect();
        let world = model.pose_transforms(&Transform::identity(), &rotations);
        model
            .fingers()
            .iter()
            .map(|finger| world[*finger.bones.last().expect("fingers have bones")] * finger.tip)
            .collect()
    };
    let (z, y) = match sidecar.and_then(|s| s.frame.as_ref()) {
        Some(frame) => frame.axes(source)?,
        None => derived_axes(
            tips(0.0),
            tips(1.0),
            model.bones()[0].rest.translation.vector,
            source,
        )?,
    };
    let frame = Rotation::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(
        nalgebra::Matrix3::from_columns(&[y.cross(&z), y, z]),
    ));
    // Current frame of the model = the root link's parent frame; new hand frame = `frame` in it.
    let to_hand = Transform::from_parts(Default::default(), frame.inverse());
    let root_name = model.bones()[0].name.clone();
    for b in parts.bones.iter_mut() {
        if b.name == root_name {
            b.rest = to_hand * b.rest;
        }
    }
    // A hinge flexes when its axis runs across the finger and the palm normal; then `close`
    // turns it toward whichever limit moves its finger's tip toward the palm. Other hinges
    // (abduction, twist) stay open.
    let across = z.cross(&y);
    let rest = vec![Rotation::identity(); model.bones().len()];
    let world = model.pose_transforms(&Transform::identity(), &rest);
    parts.close = Vec::new();
    for (i, bone) in model.bones().iter().enumerate() {
        let prehensile_core::hand::Joint::Hinge(axis) = bone.joint else {
            continue;
        };
        let Some(fi) = bone.finger else { continue };
        let world_axis = world[i].rotation * axis.axis.into_inner();
        if world_axis.dot(&across).abs() < 0.7 {
            continue;
        }
        let finger = &model.fingers()[fi];
        let tip = world[*finger.bones.last().expect("fingers have bones")] * finger.tip;
        let joint = Point3::from(world[i].translation.vector);
        // Turning by +θ about the axis moves the tip along axis × (tip − joint).
        let toward_palm = world_axis.cross(&(tip - joint)).dot(&y);
        let [lo, hi] = axis.limits;
        let target = if toward_palm >= 0.0 { hi } else { lo };
        parts
            .close
            .push((model.dof_names()[bone.first_dof].clone(), target));
    }
    if let Some(s) = sidecar.filter(|s| !s.close.is_empty()) {
        parts.close = s.close.iter().map(|(k, v)| (k.clone(), *v)).collect();
    }
    let mut hand = HandModel::from_parts(parts).map_err(err)?;
    prehensile_core::hand::movement_derivation::add_derived_movements(&mut hand);
    for (name, o) in sidecar.iter().flat_map(|s| &s.movements) {
        o.apply(&mut hand, name, source)?;
    }
    Ok(hand)
}

/// The hand frame's z (along the fingers: from the root toward the mean open fingertip) and y
/// (out of the palm: where closing moves the tips, square to z), from the fingertips `open` and
/// `closed` and the root's position, in the model's frame.
fn derived_axes(
    open: Vec<Point3>,
    closed: Vec<Point3>,
    root: Vec3,
    source: &str,
) -> Result<(Vec3, Vec3), FormatError> {
    let along = open
        .iter()
        .fold(Vec3::zeros(), |acc, t| acc + (t.coords - root))
        / open.len() as f64;
    let curl = open
        .iter()
        .zip(&closed)
        .fold(Vec3::zeros(), |acc, (a, b)| acc + (b - a));
    if along.norm() < 1e-9 {
        return Err(FormatError::new(
            source,
            "the fingertips sit on the root; cannot tell which way the fingers point",
        ));
    }
    let z = along.normalize();
    let y = curl - z * curl.dot(&z);
    if y.norm() < 1e-9 {
        return Err(FormatError::new(
            source,
            "closing the fingers (every joint to its upper limit) does not move the tips toward a palm side; check the joint limits",
        ));
    }
    Ok((z, y.normalize()))
}

/// The file name without folder and extension, to name a hand whose file names none.
pub fn file_stem(source: &str) -> String {
    std::path::Path::new(source)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(source)
        .to_string()
}

/// Most a box's two largest faces may lie beyond the capsules standing in for it, metres.
pub const BOX_FACE_TOLERANCE: f64 = 0.001;

/// Capsules standing in for a box of half extents `half` placed at `frame`, never outside it:
/// rows of capsules with the radius of the smallest half extent run along the longest side, close
/// enough that the two largest faces lie within [`BOX_FACE_TOLERANCE`] of their union, and one
/// capsule across each end closes the ends. Edges and corners come out rounded with that radius.
/// (A single capsule along the longest side with the larger other half side as its radius, as
/// before, made the Shadow hand's palm 21 mm thicker on each face.)
pub fn box_capsules(frame: &Transform, half: [f64; 3]) -> Vec<(Point3, Point3, f64)> {
    if !half.iter().all(|h| h.is_finite() && *h > 0.0) {
        // One degenerate capsule, which the hand's checks then refuse with the bone's name.
        let radius = half.iter().copied().fold(f64::INFINITY, f64::min);
        let centre = frame * Point3::origin();
        return vec![(centre, centre, radius)];
    }
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| half[b].total_cmp(&half[a]));
    let [long, mid, short] = axes;
    let radius = half[short];
    let at = |along_long: f64, along_mid: f64| {
        let mut p = Point3::origin();
        p[long] = along_long;
        p[mid] = along_mid;
        frame * p
    };
    let (reach_long, reach_mid) = (half[long] - radius, half[mid] - radius);
    let dip = BOX_FACE_TOLERANCE.min(radius);
    let spacing = 2.0 * (radius * radius - (radius - dip) * (radius - dip)).sqrt();
    let rows = if reach_mid > 1e-9 {
        (2.0 * reach_mid / spacing).ceil() as usize + 1
    } else {
        1
    };
    let mut capsules = Vec::with_capacity(rows + 2);
    for k in 0..rows {
        let u = if rows == 1 {
            0.0
        } else {
            -reach_mid + 2.0 * reach_mid * k as f64 / (rows - 1) as f64
        };
        capsules.push((at(-reach_long, u), at(reach_long, u), radius));
    }
    if rows > 1 {
        for end in [-reach_long, reach_long] {
            capsules.push((at(end, -reach_mid), at(end, reach_mid), radius));
        }
    }
    capsules
}

/// A bone part with the common defaults.
pub fn bone(name: &str, parent: Option<&str>, rest: Transform) -> BonePart {
    BonePart {
        name: name.to_string(),
        parent: parent.map(str::to_string),
        rest,
        joint: prehensile_core::hand::Joint::Fixed,
        dof_names: Vec::new(),
        capsules: Vec::new(),
        tip: None,
        finger: None,
        inertial: None,
    }
}
