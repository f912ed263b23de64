//! Command-line flags (first layer: parse and validate shapes; meaning is resolved per command).

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use prehensile_batch::BatchOptions;
use prehensile_core::parameter::UpAxis;
use prehensile_core::search::{defaults, ValidityRule};
use prehensile_formats::builtin::{DEFAULT_HAND, DEFAULT_OBJECT};
use prehensile_formats::Units;
use prehensile_sim::scenarios::{self, Scenario};
use prehensile_sim::{Engine, Settings};

/// Grasp poses for virtual hands on closed meshes.
#[derive(Debug, Parser)]
#[command(name = "prehensile", version, about, long_about = None)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// Subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check that a mesh is a closed, manifold object and report its size and volume.
    Check(CheckArgs),
    /// List the built-in hands, or describe a hand file.
    Hands(HandsArgs),
    /// Search a grasp pose for one hand and one object.
    Grasp(Box<GraspArgs>),
    /// Grasp every built-in object with every built-in hand and write the results to a folder.
    Demo(DemoArgs),
    /// Simulate a physically based hand driven by the grasp controller (Pollard & Zordan).
    Simulate(SimulateArgs),
    /// Fit a grasp controller to an example motion (.json or .bvh).
    Fit(FitArgs),
    /// Search every hand x object x movement x shoulder x seed on all cores and write a
    /// resumable Apache Parquet dataset (see docs/BATCH.md).
    Batch(BatchArgs),
    /// Serve the browser viewer (live grasp search in WebAssembly) on a local port.
    View(ViewArgs),
}

/// `prehensile view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Files to open in the page when it loads, as if dropped on it: meshes, hands, saved
    /// results (.json), animations (.glb) and simulation runs (.json).
    pub files: Vec<PathBuf>,
    /// The built viewer (`bash tools/viewer/build.sh` writes it).
    #[arg(long, default_value = "viewer/dist")]
    pub dir: PathBuf,
    /// Port on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 8000)]
    pub port: u16,
}

/// `prehensile batch`.
#[derive(Debug, Args)]
pub struct BatchArgs {
    /// Hands: built-in names or hand files (space- or comma-separated).
    #[arg(long, num_args = 1.., value_delimiter = ',', default_value = DEFAULT_HAND)]
    pub hands: Vec<String>,
    /// Objects: built-in names, mesh files, folders (their mesh files) or patterns such as
    /// 'scans/*.stl' (quoted).
    #[arg(long, num_args = 1.., value_delimiter = ',', default_values_t = prehensile_formats::BUILTIN_OBJECTS.map(String::from))]
    pub objects: Vec<String>,
    /// Movements of the hands, or auto (try each, keep the best; a movement with nothing valid after 100 steps stops once another has found its grasp).
    #[arg(long, num_args = 1.., value_delimiter = ',', default_value = defaults::MOVEMENT)]
    pub movements: Vec<String>,
    /// Shoulders: default (the hand's default for the object) or X,Y,Z (space-separated).
    #[arg(long, num_args = 1.., default_value = "default", allow_hyphen_values = true)]
    pub shoulders: Vec<String>,
    /// Seeds 1..=N of the random search angles.
    #[arg(long, default_value_t = 1)]
    pub seeds: u64,
    /// The dataset folder: created, or resumed if it holds a dataset of the same inputs.
    #[arg(long, default_value = "prehensile-dataset")]
    pub out: PathBuf,
    /// Units, scale and repair of mesh files.
    #[command(flatten)]
    pub mesh_options: MeshOptions,
    /// The world's up axis: x, y or z.
    #[arg(long, default_value_t = BatchOptions::default().up)]
    pub up: UpAxis,
    /// Coulomb friction coefficient the search assumes: force closure, ε, and how far the contact
    /// normals must spread (78° at 0.5, 59.6° at 1). The default is about half a grippy
    /// world's friction; MuJoCo holds fewer grasps searched with the full friction (docs/QUALITY.md).
    #[arg(long, default_value_t = BatchOptions::default().friction)]
    pub friction: f64,
    /// Which grasps are valid: holds, strict or thesis (see `prehensile grasp --help`).
    #[arg(long, default_value_t = BatchOptions::default().validity)]
    pub validity: ValidityRule,
    /// Steps to go on looking past a power grasp whose contacts all push from one side (see
    /// `prehensile grasp --help`).
    #[arg(long, default_value_t = BatchOptions::default().one_sided_patience)]
    pub one_sided_patience: u32,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Write a part file every this many rows (and at least every 5 s).
    #[arg(long, default_value_t = prehensile_batch::FLUSH_ROWS)]
    pub flush_rows: usize,
}

/// `prehensile simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// drop, grasp, grip-sweep, handshake, open-close or shake.
    #[arg(long, default_value_t = scenarios::defaults::SCENARIO)]
    pub scenario: Scenario,
    /// A built-in hand or a hand file (hinge, two-axis and ball joints; moving bones need mass).
    #[arg(long, default_value = scenarios::defaults::HAND)]
    pub hand: String,
    /// Objects (comma-separated built-in names or mesh files); `grasp` grasps each with the
    /// controller fitted to the first, the others searched along that controller's closing
    /// (each case reports `searched_along_example_closing`: 0 when that found no valid grasp and
    /// the hand's own movement was searched instead).
    #[arg(long, num_args = 1.., value_delimiter = ',', default_values_t = scenarios::defaults::OBJECTS.map(String::from))]
    pub object: Vec<String>,
    /// Units, scale and repair of mesh files.
    #[command(flatten)]
    pub mesh_options: MeshOptions,
    /// Grip strength α (Eq. 15–16; the paper used 0 to 0.5).
    #[arg(long, default_value_t = scenarios::defaults::ALPHA)]
    pub alpha: f64,
    /// Time step, seconds.
    #[arg(long, default_value_t = Settings::default().dt)]
    pub dt: f64,
    /// The physics: `reduced` (each hand in its joint angles on Prehensile's own dynamics and
    /// contact solver; it follows the hand model's equations of motion) or `rapier` (one body
    /// per bone joined by rapier's impulse joints; slower, docs/PERFORMANCE.md).
    #[arg(long, default_value_t = Engine::default())]
    pub engine: Engine,
    /// Simulated seconds per case (default: the scenario's own).
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Grasps per object the grasp scenarios try, searched from the default shoulder and from it
    /// turned by +30°, −30°, +60°, … about the vertical: each is checked by holding the object
    /// against gravity for 1 s under the scenario's controller, and the first that holds is run
    /// (each case reports `hold_check_shoulder_turn_deg`, `hold_check_tried`,
    /// `hold_check_held`); 1 runs the default shoulder's grasp unchecked.
    #[arg(long, default_value_t = scenarios::defaults::CANDIDATES)]
    pub candidates: usize,
    /// Rapier's solver substeps per step (default: one per millisecond of step and at least 1,
    /// so 1 at 0.2 ms and at 1 ms).
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Rapier's Gauss–Seidel sweeps over the constraints in each substep (default: one per
    /// 0.125 ms of substep and at least 3, so 3 at 0.2 ms and 8 at 1 ms).
    #[arg(long)]
    pub inner_iterations: Option<usize>,
    /// Friction coefficient of the world (the grasp scenarios search their grasps at half of it,
    /// or at all of it when half finds no valid grasp; each case reports `search_friction`).
    #[arg(long, default_value_t = Settings::default().friction)]
    pub friction: f64,
    /// Object density, kg/m³. The default (like expanded polystyrene) gives objects of
    /// 5–10 g, what the paper's soft hand can lift; try 500 to see heavier objects slip out.
    #[arg(long, default_value_t = Settings::default().object_density)]
    pub density: f64,
    /// The run report (JSON).
    #[arg(long, default_value = "run.json")]
    pub out: PathBuf,
    /// Also write the first case as an animated glTF scene (every hand, and the object).
    #[arg(long)]
    pub glb: Option<PathBuf>,
    /// Also write the first case's first hand as BVH.
    #[arg(long)]
    pub bvh: Option<PathBuf>,
}

/// `prehensile fit`.
#[derive(Debug, Args)]
pub struct FitArgs {
    /// The example motion: `prehensile.motion/1` JSON, or BVH (distance = how far the root is
    /// from where it is at the most closed frame).
    #[arg(long)]
    pub motion: Option<PathBuf>,
    /// Without --motion: fit to the synthetic example of a grasp of this object found by the
    /// search (written next to the controller: controller.motion.json for controller.toml).
    #[arg(long, default_value = DEFAULT_OBJECT)]
    pub object: String,
    /// A built-in hand or a hand file.
    #[arg(long, default_value = DEFAULT_HAND)]
    pub hand: String,
    /// The controller file to write (TOML).
    #[arg(long, default_value = "controller.toml")]
    pub out: PathBuf,
}

/// How a mesh file is read: its unit, a scale, and an optional repair.
#[derive(Debug, Args)]
pub struct MeshOptions {
    /// Multiply coordinates by this factor (after --units).
    #[arg(long, default_value_t = 1.0)]
    pub scale: f64,
    /// The file's length unit: mm, cm or m.
    #[arg(long, default_value_t = Units::default())]
    pub units: Units,
    /// Repair: merge vertices closer than this many metres first (e.g. 1e-6 for hairline seams).
    #[arg(long)]
    pub weld: Option<f64>,
}

impl MeshOptions {
    /// Metres per file unit times the scale.
    pub fn factor(&self) -> f64 {
        self.scale * self.units.metres()
    }
}

/// `prehensile check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Mesh file (.obj, .stl, .ply, .gltf, .glb).
    pub mesh: PathBuf,
    /// Units, scale and repair of the mesh.
    #[command(flatten)]
    pub mesh_options: MeshOptions,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// `prehensile hands`.
#[derive(Debug, Args)]
pub struct HandsArgs {
    /// Describe this hand file (.toml, see docs/HAND_FORMAT.md; .urdf; MJCF .xml; skinned
    /// .glb/.gltf) instead of listing the built-ins.
    #[arg(long)]
    pub file: Option<PathBuf>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// `prehensile grasp`.
#[derive(Debug, Args)]
pub struct GraspArgs {
    /// A built-in hand (human, human-left, robot3, cartoon4) or a hand file (.toml, .urdf, MJCF
    /// .xml, skinned .glb/.gltf).
    #[arg(long, default_value = DEFAULT_HAND)]
    pub hand: String,
    /// A built-in object (sphere, box, cylinder, torus, mug) or a mesh file (.obj, .stl, .ply,
    /// .gltf, .glb).
    #[arg(long, default_value = DEFAULT_OBJECT)]
    pub object: String,
    /// Units, scale and repair of the mesh.
    #[command(flatten)]
    pub mesh_options: MeshOptions,
    /// power, precision, close, any movement of the hand, or auto (try each, keep the best; a movement with nothing valid after 100 steps stops once another has found its grasp).
    #[arg(long, default_value = defaults::MOVEMENT)]
    pub movement: String,
    /// Hook position X,Y,Z in the object's frame (default: its centre of mass). A hook outside
    /// the object's material that gives no grasp pushing from every side is moved into the
    /// material once (the result's `hook` and `stats.hook_moves` say so).
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub hook: Option<[f64; 3]>,
    /// Shoulder position X,Y,Z (default: 35 cm behind, 20 cm aside and 35 cm above the hook).
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    pub shoulder: Option<[f64; 3]>,
    /// The world's up axis: x, y or z.
    #[arg(long, default_value_t = defaults::UP)]
    pub up: UpAxis,
    /// Seed of the random search angles.
    #[arg(long, default_value_t = defaults::SEED)]
    pub seed: u64,
    /// Threads evaluating each search step's candidates (default: one per core; the result is
    /// the same on any number).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Quality weights `G,F,T,W[,S]` for gDist, fDist, tDist*, wDist and the stability term ε·L
    /// (default: 5,1,0,1,0 for movements without contact fingers, Eq. 5.1; 5,0,1,1,0 for those
    /// with, Eq. 5.2; S defaults to 0).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub weights: Option<Vec<f64>>,
    /// Coulomb friction coefficient the search assumes: force closure, ε, and how far the contact
    /// normals must spread (78° at 0.5, 59.6° at 1).
    #[arg(long, default_value_t = defaults::FRICTION)]
    pub friction: f64,
    /// Which grasps are valid: `holds` (force closure, the contact normals not all within 78° of
    /// one direction at friction 0.5, 59.6° at 1, and a precision grasp's thumb and index pads
    /// opposed; a power grasp whose normals all lie in one open half-space only when the search
    /// finds none that pushes from every side), `strict` (`holds`, and a power grasp's normals never all in one open
    /// half-space, whatever the friction) or `thesis` (no penetration and enough fingers
    /// touching, §6.4.1).
    #[arg(long, default_value_t = defaults::VALIDITY)]
    pub validity: ValidityRule,
    /// With only a power grasp whose contacts all push from one side (valid under `holds`:
    /// friction holds it), go on looking this many steps for one that pushes from every side;
    /// 0 takes the first one-sided grasp found (faster where there is none, e.g. the Shadow
    /// hand's torus; docs/decisions/004-one-sided-patience.md).
    #[arg(long, default_value_t = defaults::ONE_SIDED_PATIENCE)]
    pub one_sided_patience: u32,
    /// Stop the search after about this many milliseconds, every movement of `auto` within
    /// them; a search may overrun by one slice of its work, a few milliseconds (default: run
    /// until converged). docs/PERFORMANCE.md shows what 5 to 40 ms buy.
    #[arg(long)]
    pub budget_ms: Option<f64>,
    /// Fill the object's whole distance grid before the search, on every core, instead of node by
    /// node as the search reads it: the search's own time (`stats.seconds`) then leaves the
    /// fills out, as it is from the second grasp on in a program that keeps its object. The
    /// same grasp either way; a single grasp takes longer in all.
    #[arg(long)]
    pub fill_grid: bool,
    /// Also test the grasp in the simulation (its default, reduced-coordinate engine): the hand
    /// squeezes (grip strength 0.5), then
    /// gravity pulls the object along each of the 6 axis directions for 1 s; held = moved < 2 cm
    /// and turned < 30°. Adds `hold` to the JSON.
    #[arg(long)]
    pub hold: bool,
    /// The engine of `--hold`: `reduced` (the default) or `rapier`.
    #[arg(long, default_value_t = Engine::default(), requires = "hold")]
    pub hold_engine: Engine,
    /// Write the result as JSON here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write a picture of the grasp (SVG) here.
    #[arg(long)]
    pub svg: Option<PathBuf>,
    /// Write a glTF binary scene here: the object, the hand's capsules and an animation of the
    /// approach and closing (opens in Blender and three.js).
    #[arg(long)]
    pub glb: Option<PathBuf>,
    /// Write the same motion as BVH (joint rotations, centimetres) here.
    #[arg(long)]
    pub bvh: Option<PathBuf>,
}

/// `prehensile demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Folder for the results.
    #[arg(long, default_value = "prehensile-demo")]
    pub out: PathBuf,
    /// Seed of the random search angles.
    #[arg(long, default_value_t = defaults::SEED)]
    pub seed: u64,
    /// The built browser viewer (`bash tools/viewer/build.sh`), copied into the demo folder as
    /// `viewer/` so that its page opens from the folder itself; left out, with a note in the
    /// gallery, when it is not built.
    #[arg(long, default_value = "viewer/dist")]
    pub viewer: PathBuf,
}

/// Parses `X,Y,Z`.
pub fn parse_point(s: &str) -> Result<[f64; 3], String> {
    parse_numbers::<3>(s, "three numbers X,Y,Z")
}

/// Parses `N` comma-separated numbers (the library checks their values).
fn parse_numbers<const N: usize>(s: &str, what: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!("'{s}' should be {what}"));
    }
    let mut p = [0.0f64; N];
    for (slot, part) in p.iter_mut().zip(&parts) {
        *slot = part
            .parse()
            .map_err(|_| format!("'{part}' in '{s}' is not a number"))?;
    }
    Ok(p)
}
