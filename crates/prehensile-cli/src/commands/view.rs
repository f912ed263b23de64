//! `prehensile view [FILES…]`: serves the browser viewer (built by `tools/viewer/build.sh` into
//! `viewer/dist`) on a local port. A few lines of `std::net` rather than an HTTP crate: the server
//! answers GET requests on 127.0.0.1 for the viewer's own files, and for the files named on the
//! command line (`/open/list.json` lists their names, `/open/K` is the K-th), which the page
//! opens when it loads; nothing else.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::args::ViewArgs;
use crate::CliError;

/// Largest request line or header line read, bytes.
const MAX_LINE: u64 = 8192;

/// Runs the server until interrupted.
pub fn run(args: &ViewArgs) -> Result<i32, CliError> {
    let index = args.dir.join("index.html");
    if !index.is_file() || !args.dir.join("main.js").is_file() {
        return Err(CliError::Usage(format!(
            "{} holds no built viewer (index.html, main.js); build it with `bash tools/viewer/build.sh` \
             (needs the wasm32-unknown-unknown target, wasm-bindgen and npm), or pass --dir",
            args.dir.display()
        )));
    }
    for file in &args.files {
        // Read once now, so that a missing or unreadable file is an error here, not a 404 later.
        prehensile_formats::read_input(file, prehensile_formats::MAX_MESH_BYTES)?;
    }
    let files = Arc::new(args.files.clone());
    let listener = TcpListener::bind(("127.0.0.1", args.port))
        .map_err(|e| CliError::Usage(format!("cannot listen on 127.0.0.1:{}: {e}", args.port)))?;
    let port = listener
        .local_addr()
        .map_err(|e| CliError::Usage(format!("cannot listen on 127.0.0.1:{}: {e}", args.port)))?
        .port();
    out!(
        "serving the viewer from {} at http://127.0.0.1:{port}/ (Ctrl-C stops)",
        args.dir.display()
    );
    for stream in listener.incoming().flatten() {
        let (index, files) = (index.clone(), Arc::clone(&files));
        std::thread::spawn(move || {
            let _ = answer(stream, &index, &files);
        });
    }
    Ok(0)
}

fn content_type(path: &Path) -> &'static str {
    match path.extension().and_then(|e| e.to_str()) {
        Some("html") => "text/html; charset=utf-8",
        Some("js") => "text/javascript",
        Some("wasm") => "application/wasm",
        Some("json" | "map") => "application/json",
        Some("png") => "image/png",
        Some("glb") => "model/gltf-binary",
        _ => "application/octet-stream",
    }
}

/// Answers one request: a file of the viewer's folder or one of the `files` to open, or 404
/// (anything else, or not a regular file), or 405 (not GET).
fn answer(stream: TcpStream, index: &Path, files: &[PathBuf]) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?.take(64 * MAX_LINE));
    let mut request = String::new();
    reader.by_ref().take(MAX_LINE).read_line(&mut request)?;
    // Drain the headers (bounded by the reader's limit).
    let mut line = String::new();
    while reader.by_ref().take(MAX_LINE).read_line(&mut line)? > 2 {
        line.clear();
    }
    let mut parts = request.split_whitespace();
    let (method, target) = (parts.next().unwrap_or(""), parts.next().unwrap_or("/"));
    let mut stream = stream;
    if method != "GET" {
        return stream.write_all(b"HTTP/1.1 405 Method Not Allowed\r\ncontent-length: 0\r\n\r\n");
    }
    let path = target.split(['?', '#']).next().unwrap_or("/");
    let relative = match path.trim_start_matches('/') {
        "" => "index.html",
        p => p,
    };
    let read = |f: &Path| {
        prehensile_formats::read_input(f, prehensile_formats::MAX_MESH_BYTES)
            .ok()
            .map(|b| (f.to_path_buf(), b))
    };
    let file = match relative.strip_prefix("open/") {
        Some("list.json") => {
            let names: Vec<String> = files
                .iter()
                .map(|f| {
                    f.file_name()
                        .unwrap_or_default()
                        .to_string_lossy()
                        .into_owned()
                })
                .collect();
            let json = serde_json::to_vec(&names).unwrap_or_default();
            Some((PathBuf::from("list.json"), json))
        }
        Some(k) => k
            .parse::<usize>()
            .ok()
            .and_then(|k| files.get(k))
            .and_then(|f| read(f)),
        None => prehensile_formats::confined(index, relative)
            .ok()
            .and_then(|f| read(&f)),
    };
    match file {
        Some((f, bytes)) => {
            write!(
                stream,
                "HTTP/1.1 200 OK\r\ncontent-type: {}\r\ncontent-length: {}\r\ncache-control: no-cache\r\n\r\n",
                content_type(&f),
                bytes.len()
            )?;
            stream.write_all(&bytes)
        }
        None => stream.write_all(b"HTTP/1.1 404 Not Found\r\ncontent-length: 0\r\n\r\n"),
    }
}
