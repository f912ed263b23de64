//! `prehensile view`: serves the viewer's folder on 127.0.0.1 and nothing outside it.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};

fn get(port: u16, target: &str) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(("127.0.0.1", port)).unwrap();
    write!(s, "GET {target} HTTP/1.1\r\nhost: x\r\n\r\n").unwrap();
    let mut reply = Vec::new();
    s.read_to_end(&mut reply).unwrap();
    let text = String::from_utf8_lossy(&reply);
    let code = text[9..12].parse().unwrap();
    let body = reply[text.find("\r\n\r\n").unwrap() + 4..].to_vec();
    (code, body)
}

#[test]
fn the_viewer_folder_is_served_and_nothing_outside_it() {
    let root = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("prehensile-view-{}", std::process::id()));
    let dist = root.join("dist");
    std::fs::create_dir_all(&dist).unwrap();
    std::fs::write(dist.join("index.html"), "<!doctype html>viewer").unwrap();
    std::fs::write(dist.join("main.js"), "console.log(1)").unwrap();
    std::fs::write(root.join("secret.txt"), "not for the browser").unwrap();
    let result = root.join("saved.json");
    std::fs::write(&result, r#"{"schema": "prehensile.grasp/3"}"#).unwrap();
    let mut server = Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .args(["view", "--port", "0", "--dir", dist.to_str().unwrap()])
        .arg(&result)
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let mut line = String::new();
    BufReader::new(server.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let port: u16 = line
        .rsplit(':')
        .next()
        .and_then(|p| p.split('/').next())
        .unwrap()
        .parse()
        .unwrap();
    let checks = std::panic::catch_unwind(|| {
        assert_eq!(get(port, "/"), (200, b"<!doctype html>viewer".to_vec()));
        assert_eq!(get(port, "/main.js?v=2").0, 200);
        // The files named on the command line, for the page to open, and only those.
        assert_eq!(
            get(port, "/open/list.json"),
            (200, br#"["saved.json"]"#.to_vec())
        );
        assert_eq!(
            get(port, "/open/0"),
            (200, br#"{"schema": "prehensile.grasp/3"}"#.to_vec())
        );
        assert_eq!(get(port, "/open/1").0, 404);
        assert_eq!(get(port, "/open/../secret.txt").0, 404);
        for outside in [
            "/../secret.txt",
            "/%2e%2e/secret.txt",
            "//etc/passwd",
            "/missing.js",
        ] {
            assert_eq!(get(port, outside).0, 404, "{outside}");
        }
    });
    server.kill().unwrap();
    server.wait().unwrap();
    checks.unwrap();
    // A file to open that is not there is an error at once, naming it.
    let out = Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .args(["view", "--dir", dist.to_str().unwrap()])
        .arg(root.join("missing.json"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing.json"));
    // Without a built viewer it says how to build one.
    let out = Command::new(env!("CARGO_BIN_EXE_prehensile"))
        .args(["view", "--dir", root.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("tools/viewer/build.sh"));
}
