//! `glint serve`: the GPU image, the CPU f64 reference, the error map and
//! each pixel's ray tree on a page served from this machine, following the
//! scene and shader files as they change (docs/guide.md, A live page).
//!
//! The page asks for `/state?after=N`, which is answered as soon as what
//! it shows changes past version N: an update reaches every open page
//! without a reload, through plain requests that the HTTP crate serves
//! whole (a stream's chunks would wait in its buffers). Nothing a request
//! says names a file, writes one or changes an option: the routes below
//! are all there is, and anything else is a 404.

mod explained;
mod state;
mod worker;

use std::io::Cursor;
use std::net::{IpAddr, SocketAddr};
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{self, Sender};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use anyhow::Context;
use clap::Args;
use tiny_http::{Header, Request, Response, Server, StatusCode};

use super::console::{errln, outln};
use super::{DeviceArgs, SceneArgs};
use state::State;
use worker::{Job, Queue};

#[derive(Args)]
pub struct ServeArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The port to listen on; 0 picks a free one.
    #[arg(long, default_value_t = 0)]
    port: u16,
    /// The address to listen on. Anyone who can reach an address other than the loopback sees the scene's images.
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1")]
    bind: IpAddr,
    #[command(flatten)]
    device: DeviceArgs,
}

/// The page: one HTML file with its script, built in.
const PAGE: &str = include_str!("page.html");

/// Requests answered at once; past this a request gets 503. A page holds
/// one waiting for the next state and makes a few more at a change.
const MAX_REQUESTS: usize = 32;

/// How long a `/state?after=N` waits for a change before it answers with
/// the state as it is.
const LONGEST_WAIT: Duration = Duration::from_secs(20);

/// The longest request line glint reads; every route is short.
const MAX_URL: usize = 256;

pub fn run(a: &ServeArgs) -> anyhow::Result<ExitCode> {
    super::console::exit_at_once_when_interrupted();
    // A scene that cannot be read at all is a mistyped name: one error, as
    // every command gives it. A scene that reads but is wrong is served,
    // its error on the page until it is mended.
    if !a.scene.scene.is_file() {
        a.scene.load()?;
    }
    let options = a.device.options()?;
    options.check()?;
    let renderer = super::render_gpu::open(&options)?;
    let server = Server::http(SocketAddr::new(a.bind, a.port)).map_err(|e| {
        anyhow::anyhow!("cannot listen on {}: {e}", SocketAddr::new(a.bind, a.port))
    })?;
    let addr = server
        .server_addr()
        .to_ip()
        .context("the server has no IP address")?;
    let state = Arc::new(State::default());
    state.change(|s| s.status.scene = a.scene.scene.display().to_string());
    let (jobs, waiting) = mpsc::channel();
    let queue = Arc::new(Queue::default());
    {
        let (scene, device, state, queue) = (
            a.scene.clone(),
            a.device.clone(),
            state.clone(),
            queue.clone(),
        );
        std::thread::Builder::new()
            .name("glint-render".to_owned())
            .spawn(move || {
                worker::render_thread(scene, device, options, renderer, state, waiting, queue)
            })
            .context("cannot start the render thread")?;
    }
    {
        let (state, queue, jobs, accel) =
            (state.clone(), queue.clone(), jobs.clone(), a.device.accel);
        std::thread::Builder::new()
            .name("glint-reference".to_owned())
            .spawn(move || worker::reference_thread(state, queue, jobs, accel))
            .context("cannot start the reference thread")?;
    }
    if !a.bind.is_loopback() {
        errln!("warning: listening on {addr}: anyone who can reach it sees this scene's images");
    }
    outln!("serving {} at http://{addr}/", a.scene.scene.display());
    let jobs = Arc::new(Mutex::new(jobs));
    let active = Arc::new(AtomicUsize::new(0));
    for request in server.incoming_requests() {
        if active.fetch_add(1, Ordering::SeqCst) >= MAX_REQUESTS {
            active.fetch_sub(1, Ordering::SeqCst);
            let _ = request.respond(text(503, "too many requests at once"));
            continue;
        }
        let (state, jobs, done) = (state.clone(), jobs.clone(), active.clone());
        let spawned = std::thread::Builder::new()
            .name("glint-request".to_owned())
            .spawn(move || {
                answer(request, &state, &jobs);
                done.fetch_sub(1, Ordering::SeqCst);
            });
        if spawned.is_err() {
            active.fetch_sub(1, Ordering::SeqCst);
        }
    }
    anyhow::bail!("the server stopped taking requests")
}

fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("a header of ASCII")
}

fn text(status: u16, body: &str) -> Response<Cursor<Vec<u8>>> {
    bytes(
        status,
        "text/plain; charset=utf-8",
        body.as_bytes().to_vec(),
    )
}

fn bytes(status: u16, kind: &str, body: Vec<u8>) -> Response<Cursor<Vec<u8>>> {
    Response::from_data(body)
        .with_status_code(StatusCode(status))
        .with_header(header("Content-Type", kind))
        .with_header(header("Cache-Control", "no-store"))
        .with_header(header("X-Content-Type-Options", "nosniff"))
}

/// Answers one request: a route below, else 404.
fn answer(request: Request, state: &State, jobs: &Mutex<Sender<Job>>) {
    let response = route(&request, state, jobs);
    let _ = request.respond(response);
}

fn route(request: &Request, state: &State, jobs: &Mutex<Sender<Job>>) -> Response<Cursor<Vec<u8>>> {
    use tiny_http::Method;
    if !matches!(request.method(), Method::Get | Method::Head) {
        return text(405, "only GET");
    }
    // No request carries a body: one that says it does is refused unread.
    if request.body_length().is_some_and(|n| n > 0)
        || request
            .headers()
            .iter()
            .any(|h| h.field.equiv("Transfer-Encoding"))
    {
        return text(413, "no request has a body");
    }
    let url = request.url();
    if url.len() > MAX_URL {
        return text(414, "the address is too long");
    }
    let (path, query) = url.split_once('?').unwrap_or((url, ""));
    match path {
        "/" => bytes(200, "text/html; charset=utf-8", PAGE.as_bytes().to_vec()).with_header(
            header(
                "Content-Security-Policy",
                "default-src 'self'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src 'self' blob:",
            ),
        ),
        "/state" => {
            let after = number(query, "after").unwrap_or(0);
            let status = match state.after(after, LONGEST_WAIT) {
                Some(s) => s,
                None => state.lock().status.clone(),
            };
            bytes(
                200,
                "application/json",
                serde_json::to_vec(&status).unwrap_or_default(),
            )
        }
        "/gpu.png" | "/reference.png" | "/error.png" | "/gpu.f32" | "/reference.f32" => {
            let shown = state.lock();
            let frame = match path {
                "/gpu.png" | "/gpu.f32" => shown.gpu.as_ref(),
                "/reference.png" | "/reference.f32" => shown.reference.as_ref(),
                _ => shown.error_map.as_ref(),
            };
            let Some(frame) = frame else {
                return text(404, "no such image yet");
            };
            let r = if path.ends_with(".png") {
                bytes(200, "image/png", frame.png.clone())
            } else {
                bytes(200, "application/octet-stream", frame.floats.clone())
            };
            r.with_header(header("X-Glint-Generation", &frame.generation.to_string()))
        }
        "/explain" => {
            let coordinate = |key| number(query, key).and_then(|n| u32::try_from(n).ok());
            let (Some(x), Some(y)) = (coordinate("x"), coordinate("y")) else {
                return text(400, "explain takes ?x=X&y=Y, two whole numbers");
            };
            let (reply, answer) = mpsc::channel();
            let sent = jobs
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .send(Job::Explain { x, y, reply });
            if sent.is_err() {
                return text(503, "the render thread has stopped");
            }
            match answer.recv_timeout(Duration::from_secs(300)) {
                Ok(Ok(json)) => bytes(200, "application/json", json.into_bytes()),
                Ok(Err(e)) => bytes(
                    200,
                    "application/json",
                    serde_json::to_vec(&serde_json::json!({ "error": e })).unwrap_or_default(),
                ),
                Err(_) => text(503, "the explanation did not come"),
            }
        }
        _ => text(404, "not found"),
    }
}

/// The whole number `key=N` of a query, where it is one.
fn number(query: &str, key: &str) -> Option<u64> {
    query
        .split('&')
        .filter_map(|kv| kv.split_once('='))
        .find(|(k, _)| *k == key)
        .and_then(|(_, v)| {
            (!v.is_empty() && v.len() <= 19 && v.bytes().all(|b| b.is_ascii_digit()))
                .then(|| v.parse().ok())
                .flatten()
        })
}
