//! Writes every built-in object as OBJ into the folder given as the first argument, for
//! independent programs (e.g. the collision oracle in `tools/oracle`) to read.

use prehensile_core::shapes::{builtin_object, BUILTIN_OBJECTS};

fn main() -> std::io::Result<()> {
    let dir = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    std::fs::create_dir_all(&dir)?;
    for name in BUILTIN_OBJECTS {
        let mesh = builtin_object(name).expect("listed objects exist");
        let path = std::path::Path::new(&dir).join(format!("{name}.obj"));
        std::fs::write(&path, prehensile_formats::write_obj(&mesh))?;
        println!("{}", path.display());
    }
    Ok(())
}
