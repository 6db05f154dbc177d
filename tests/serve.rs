//! `glint serve` as a person uses it: its page in a real browser (Debian's
//! headless Chromium, driven through its DevTools protocol), a scene edited
//! and a shader broken and mended under it, a pixel clicked; and as a
//! hostile client meets it: paths out of its routes, methods and bodies it
//! does not take, and a SIGTERM that must leave nothing behind.

#![cfg(feature = "gpu")]

mod common;

use std::time::Duration;

use serde_json::json;

use common::page::{first_material, recolour, scene_copy, Browser, Served};

/// The size the tests serve at.
const SMALL: &[&str] = &["--width", "64", "--height", "48"];

/// The page's box of element `id`: left, top (CSS pixels).
fn corner(b: &mut Browser, id: &str) -> (f64, f64) {
    let r = b.eval(&format!(
        "(() => {{ const r = document.getElementById('{id}').getBoundingClientRect(); return [r.left, r.top]; }})()"
    ));
    (r[0].as_f64().unwrap(), r[1].as_f64().unwrap())
}

#[test]
fn the_page_shows_the_images_follows_an_edit_and_explains_a_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let scene = scene_copy(dir.path(), "seed-fig3.toml");
    let served = Served::start(&scene, SMALL, &tmp);
    let mut b = Browser::open(&served.url);
    b.until(
        "document.body.dataset.judged === 'yes' && document.getElementById('gpu').complete \
         && document.getElementById('reference').complete",
        "a judged first render",
    );
    let verdict = b.eval("document.getElementById('verdict').textContent");
    assert!(verdict.as_str().unwrap().contains(": pass"), "{verdict}");
    assert!(b.eval("document.getElementById('gpu').naturalWidth") == json!(64));
    assert!(b.eval("document.getElementById('reference').naturalWidth") == json!(64));
    let before = b.screenshot();
    // A material's colour changed: the new image comes without a reload,
    // and the screenshot changes inside the GPU image.
    let material = first_material(&scene);
    b.eval("window.notReloaded = true");
    recolour(&scene, &material, "0.9, 0.05, 0.6");
    b.until(
        "document.body.dataset.generation === '2' && document.getElementById('gpu').complete \
         && document.getElementById('gpu').src.includes('g=2')",
        "the second render",
    );
    assert_eq!(
        b.eval("window.notReloaded === true"),
        json!(true),
        "the page reloaded"
    );
    std::thread::sleep(Duration::from_millis(300));
    let after = b.screenshot();
    let (x0, y0) = corner(&mut b, "gpu");
    let changed = (0..48u32)
        .flat_map(|y| (0..64u32).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (sx, sy) = (x0 as u32 + x, y0 as u32 + y);
            before.get_pixel(sx, sy) != after.get_pixel(sx, sy)
        })
        .count();
    assert!(
        changed > 20,
        "{changed} pixels of the GPU image changed on screen"
    );
    // A pixel clicked: its tree, whose GPU colour is the float image's
    // value at that pixel; the arrow keys move to the next one.
    // The click lands where the page's layout puts it (a box may start at
    // a fraction of a pixel): the pixel the page took is the one checked.
    b.eval("document.body.dataset.explained = ''");
    b.click(x0 + 32.5, y0 + 30.5);
    b.until(
        "/^\\d+,\\d+$/.test(document.body.dataset.explained || '')",
        "the pixel's tree",
    );
    let picked = b.eval("document.body.dataset.explained");
    let (px, py) = picked.as_str().unwrap().split_once(',').unwrap();
    let (px, py): (u32, u32) = (px.parse().unwrap(), py.parse().unwrap());
    assert!(
        px.abs_diff(32) <= 1 && py.abs_diff(30) <= 1,
        "clicked {px},{py}"
    );
    let tree = b.eval("document.querySelector('.tree-color').dataset.gpu");
    let tree: Vec<f64> = serde_json::from_str(tree.as_str().unwrap()).unwrap();
    let value = b.eval(&format!("valueAt('gpu', {px}, {py})"));
    let value: Vec<f64> = serde_json::from_value(value).unwrap();
    for (t, v) in tree.iter().zip(&value) {
        assert!(
            (t - v).abs() <= 1e-6 * t.abs().max(1e-3),
            "the tree's colour {tree:?} is not the image's {value:?}"
        );
    }
    let rows = b.eval("document.querySelectorAll('#explain tr').length");
    assert!(rows.as_u64().unwrap() > 10, "{rows} rows");
    b.key("ArrowRight");
    b.until(
        &format!("document.body.dataset.explained === '{},{py}'", px + 1),
        "the next pixel's tree",
    );
    // docs/img/serve.png is this page at zoom 4:
    // GLINT_SERVE_SCREENSHOT=docs/img/serve.png cargo test --test serve the_page
    if let Ok(path) = std::env::var("GLINT_SERVE_SCREENSHOT") {
        b.eval("(() => { const z = document.getElementById('zoom'); z.value = '4'; z.dispatchEvent(new Event('change')); })()");
        std::thread::sleep(Duration::from_millis(500));
        b.screenshot().save(path).unwrap();
    }
}

#[test]
fn a_broken_shader_shows_its_error_and_the_fix_brings_the_image_back() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let scene = scene_copy(dir.path(), "seed-fig3.toml");
    let include = dir.path().join("inc");
    std::fs::create_dir(&include).unwrap();
    let shade = include.join("shade.glsl");
    let good = std::fs::read_to_string(common::repo().join("shaders/shade.glsl")).unwrap();
    std::fs::write(&shade, &good).unwrap();
    let served = Served::start(
        &scene,
        &[SMALL, &["-I", include.to_str().unwrap()]].concat(),
        &tmp,
    );
    let mut b = Browser::open(&served.url);
    b.until(
        "document.body.dataset.generation === '1'",
        "the first render",
    );
    std::fs::write(&shade, format!("{good}\nthis is not GLSL;\n")).unwrap();
    b.until(
        "document.getElementById('error').textContent.includes('shade.glsl:')",
        "the compile error",
    );
    let error = b.eval("document.getElementById('error').textContent");
    assert!(error.as_str().unwrap().starts_with("error: "), "{error}");
    // The last good image stays.
    assert_eq!(
        b.eval("document.getElementById('gpu').naturalWidth"),
        json!(64)
    );
    std::fs::write(&shade, &good).unwrap();
    b.until(
        "document.getElementById('error').textContent === '' && document.body.dataset.generation === '2'",
        "the image back",
    );
}

#[test]
fn it_serves_its_routes_alone_on_the_loopback_and_leaves_nothing_behind() {
    let dir = tempfile::tempdir().unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let scene = scene_copy(dir.path(), "seed-fig3.toml");
    let mut served = Served::start(&scene, SMALL, &tmp);
    assert!(served.get("/").starts_with("HTTP/1.1 200"));
    for path in [
        "/../../etc/passwd",
        "/%2e%2e/%2e%2e/etc/passwd",
        "/..%2f..%2fetc%2fpasswd",
        "//etc/passwd",
        "/gpu.png/../../../etc/passwd",
        "/index.html",
        "/state/../../etc/passwd",
    ] {
        let status = served.get(path);
        assert!(status.starts_with("HTTP/1.1 404"), "{path}: {status}");
    }
    let post = served.raw(
        b"POST /state HTTP/1.1\r\nHost: x\r\nContent-Length: 3\r\nConnection: close\r\n\r\nabc",
    );
    assert!(post.starts_with("HTTP/1.1 405"), "{post}");
    let body = served.raw(
        b"GET /state HTTP/1.1\r\nHost: x\r\nContent-Length: 3\r\nConnection: close\r\n\r\nabc",
    );
    assert!(body.starts_with("HTTP/1.1 413"), "{body}");
    let long = served.get(&format!("/explain?x=1&y={}", "1".repeat(400)));
    assert!(long.starts_with("HTTP/1.1 414"), "{long}");
    let bad = served.get("/explain?x=-1&y=2");
    assert!(bad.starts_with("HTTP/1.1 400"), "{bad}");
    // The loopback alone: its socket's local address in /proc/net/tcp.
    let tcp = std::fs::read_to_string("/proc/net/tcp").unwrap();
    let port = format!(":{:04X} ", served.port);
    let listening: Vec<&str> = tcp
        .lines()
        .filter(|l| {
            l.split_whitespace()
                .nth(1)
                .is_some_and(|a| format!("{a} ").ends_with(&port))
        })
        .filter(|l| l.split_whitespace().nth(3) == Some("0A"))
        .collect();
    assert_eq!(listening.len(), 1, "{listening:?}");
    assert!(
        listening[0]
            .split_whitespace()
            .nth(1)
            .unwrap()
            .starts_with("0100007F:"),
        "{listening:?}"
    );
    // SIGTERM: exit 130, no process and no temporary file left.
    // SAFETY: signals the child this test started.
    unsafe { libc::kill(served.child.id() as libc::pid_t, libc::SIGTERM) };
    let status = served.child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    let name = scene.to_string_lossy().into_owned();
    let left: Vec<String> = common::command_lines()
        .into_iter()
        .filter(|c| c.contains("serve") && c.contains(&name))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    assert_eq!(std::fs::read_dir(&tmp).unwrap().count(), 0);
    let mut files: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    files.sort();
    assert_eq!(files, ["scene.toml", "tmp"]);
}

/// A scene that cannot be read at all is a mistyped name: one error and
/// exit 2, not a page of it.
#[test]
fn a_scene_that_cannot_be_read_is_one_error() {
    let o = common::glint(&["serve", "/nonexistent/scene.toml"]);
    common::assert_user_error(&o, "cannot read scene");
    assert!(o.stdout.is_empty(), "it served");
}
