//! Structure-aware MJCF include trees: up to eight files that include each other by arbitrary
//! paths (plain, in a subfolder, `..` escapes, absolute, empty, inside comments), with repeats,
//! cycles and fan-out, each carrying a fragment (a small valid hand, defaults, garbage), loaded
//! from the first file. Nothing may panic, hang, exhaust memory or read outside the folder.
#![no_main]

use std::fmt::Write as _;
use std::path::PathBuf;

use arbitrary::Arbitrary;

#[derive(Arbitrary, Debug)]
struct File {
    /// (path kind, target file) of each include.
    includes: Vec<(u8, u8)>,
    fragment: u8,
    in_subfolder: bool,
}

const HAND: &str = r#"<worldbody><body name="palm"><geom type="capsule" fromto="0 0 0 0 0 0.08" size="0.02"/>
<body name="index" pos="0.02 0 0.08"><joint name="i1" type="hinge" axis="1 0 0" range="0 1.5"/><geom type="capsule" fromto="0 0 0 0 0 0.04" size="0.008"/>
<body name="index_tip" pos="0 0 0.04"><joint name="i2" type="hinge" axis="1 0 0" range="0 1.5"/><geom type="capsule" fromto="0 0 0 0 0 0.03" size="0.007"/></body></body>
<body name="thumb" pos="-0.02 0 0.04"><joint name="t1" type="hinge" axis="0 1 0" range="0 1.5"/><geom type="capsule" fromto="0 0 0 0 0 0.04" size="0.009"/></body>
</body></worldbody>"#;
const FRAGMENTS: [&str; 6] = [
    "",
    HAND,
    r#"<default><joint damping="0.1"/><default class="a"><geom size="0.01"/></default></default>"#,
    "<<not xml",
    r#"<compiler angle="degree"/>"#,
    r#"<tendon><fixed name="t"><joint joint="i2" coef="1"/><joint joint="i1" coef="-1"/></fixed></tendon>"#,
];

fn folder() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("prehensile-fuzz-includes-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("sub")).expect("the temporary folder is writable");
    dir
}

libfuzzer_sys::fuzz_target!(|files: Vec<File>| {
    if files.is_empty() || files.len() > 8 {
        return;
    }
    let dir = folder();
    let n = files.len();
    for (k, file) in files.iter().enumerate() {
        let mut text = String::from("<mujoco model=\"fuzz\">");
        for &(kind, target) in file.includes.iter().take(16) {
            let t = target as usize % n;
            let sub = if files[t].in_subfolder { "sub/" } else { "" };
            let path = match kind % 7 {
                0 => format!("{sub}f{t}.xml"),
                1 => format!("sub/../{sub}f{t}.xml"),
                2 => format!("../f{t}.xml"),
                3 => "/etc/passwd".to_string(),
                4 => String::new(),
                5 => format!("{sub}f{t}.xml\0"),
                _ => {
                    let _ = write!(text, "<!-- <include file=\"{sub}f{t}.xml\"/> -->");
                    continue;
                }
            };
            let _ = write!(text, "<include file=\"{}\"/>", path.replace('\0', ""));
        }
        text.push_str(FRAGMENTS[file.fragment as usize % FRAGMENTS.len()]);
        text.push_str("</mujoco>");
        let place = if file.in_subfolder { dir.join("sub") } else { dir.clone() };
        std::fs::write(place.join(format!("f{k}.xml")), text).expect("writable");
    }
    let first = if files[0].in_subfolder { dir.join("sub/f0.xml") } else { dir.join("f0.xml") };
    let _ = prehensile_formats::load_hand(&first);
});
