//! Benchmark (not a test): N WebSocket clients watch one long move; each counts the joint
//! states it receives while the arm moves, the largest gap between two of them as received,
//! and the largest gap between their send times (`t_ms`, stamped by the service's publisher):
//! the first includes the clients' own scheduling on the shared cores, the second is the
//! service's; and the delivery delay of every state (receipt minus send stamp). Then J jobs
//! are queued at once and must run in submission order.
//!
//! The service runs as it does under `reach serve` ([`reach_serve::serve`], its own process:
//! this example started again with `--service`), and the clients in this process, all on one
//! thread (tokio, as a browser's event loop would), stamping each message as it arrives.
//!
//! `cargo run --release -p reach-serve --example ws_clients -- [CLIENTS] [SECONDS] [JOBS]`
//! (defaults 100, 60, 1000).

use std::io::{BufRead as _, BufReader};
use std::net::SocketAddr;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use futures_util::StreamExt as _;
use reach::jobs::RobotInput;
use reach_serve::Config;
use serde_json::Value;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let [flag, dir, speed] = args.as_slice()
        && flag == "--service"
    {
        return service(dir, speed.parse().expect("speed"));
    }
    let numbers: Vec<f64> = args.iter().filter_map(|a| a.parse().ok()).collect();
    let clients = numbers.first().map_or(100, |&v| v as usize);
    let seconds = numbers.get(1).copied().unwrap_or(60.0);
    let jobs = numbers.get(2).map_or(1000, |&v| v as usize);
    let dir = std::env::temp_dir().join(format!("reach-ws-bench-{}", std::process::id()));
    let runtime = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();

    let (child, addr) = start_service(&dir, 1.0);
    let watchers: Vec<_> = runtime.block_on(async {
        let mut sockets = Vec::new();
        for _ in 0..clients {
            let (ws, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/ws")).await.expect("connect");
            sockets.push(ws);
        }
        sockets.into_iter().map(|ws| runtime.spawn(watch(ws))).collect()
    });
    let body = format!(r#"{{"kind": "move", "to_deg": [90, -45, 30, 0, 0, 10], "duration_s": {seconds}}}"#);
    let results: Vec<Watched> = runtime.block_on(async {
        tokio::task::spawn_blocking(move || post(addr, &body)).await.expect("POST /jobs");
        futures_util::future::join_all(watchers).await.into_iter().map(Result::unwrap).collect()
    });
    stop_service(child, &dir);

    let mut delays: Vec<i64> = results.iter().flat_map(|r| r.delays.iter().copied()).collect();
    delays.sort_unstable();
    let at = |p: f64| delays.get(((delays.len().saturating_sub(1)) as f64 * p) as usize).copied().unwrap_or(0);
    let min_count = results.iter().map(|r| r.count).min().unwrap_or(0);
    let worst_gap = results.iter().map(|r| r.max_gap).max().unwrap_or_default();
    let worst_sent_gap = results.iter().map(|r| r.max_sent_gap).max().unwrap_or_default();
    let late: usize = results.iter().map(|r| r.late).sum();
    let total: usize = results.iter().map(|r| r.count).sum();
    println!(
        "{clients} clients, {seconds} s move: fewest states per client {min_count} ({:.1} Hz); largest gap as sent \
         {worst_sent_gap} ms, as received {:.1} ms; {late} of {total} states received over 30 ms after the previous",
        min_count as f64 / seconds,
        worst_gap.as_secs_f64() * 1e3
    );
    println!(
        "delivery (receipt - send stamp, ms): median {}, p99 {}, p99.9 {}, max {}",
        at(0.5),
        at(0.99),
        at(0.999),
        delays.last().copied().unwrap_or(0)
    );

    // J jobs queued at once, run in order (0.5 s moves at 100x).
    let (child, addr) = start_service(&dir, 100.0);
    let started = Instant::now();
    let ids: Vec<i64> = (0..jobs)
        .map(|k| {
            let to = if k % 2 == 0 { 1 } else { 0 };
            let reply =
                post(addr, &format!(r#"{{"kind": "move", "to_deg": [{to}, 0, 0, 0, 0, 0], "duration_s": 0.5}}"#));
            reply["id"].as_i64().unwrap()
        })
        .collect();
    let accepted = started.elapsed();
    let last = *ids.last().unwrap();
    loop {
        let job = get(addr, &format!("/jobs/{last}"));
        if job["status"] == "done" {
            break;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let list = get(addr, &format!("/jobs?limit={jobs}"));
    let rows = list.as_array().unwrap();
    let in_order = rows.windows(2).all(|w| w[0]["updated_ms"].as_i64() <= w[1]["updated_ms"].as_i64());
    let done = rows.iter().filter(|r| r["status"] == "done").count();
    println!(
        "{jobs} jobs: accepted in {:.2} s, all executed in {:.2} s, {done} done, finished in submission order: {in_order}",
        accepted.as_secs_f64(),
        started.elapsed().as_secs_f64()
    );
    stop_service(child, &dir);
}

/// What one client saw while the arm moved.
struct Watched {
    count: usize,
    max_gap: Duration,
    max_sent_gap: i64,
    late: usize,
    delays: Vec<i64>,
}

/// The fields of a WebSocket message a client looks at (the rest is skipped unparsed, so
/// that one thread keeps up with 100 clients and the delays measured are the service's).
#[derive(serde::Deserialize)]
struct Message {
    #[serde(rename = "type")]
    kind: String,
    status: Option<String>,
    t_ms: Option<i64>,
}

/// One client: reads messages until the job is done, stamping each as it arrives.
async fn watch(
    mut ws: tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>,
) -> Watched {
    let mut seen = Watched { count: 0, max_gap: Duration::ZERO, max_sent_gap: 0, late: 0, delays: Vec::new() };
    let (mut last, mut last_sent, mut moving) = (None::<Instant>, None::<i64>, false);
    while let Some(Ok(message)) = ws.next().await {
        let (now, now_ms) = (Instant::now(), reach_serve::db::now_ms());
        let Ok(text) = message.to_text() else { continue };
        let Ok(v) = serde_json::from_str::<Message>(text) else { continue };
        if v.kind == "job" && v.status.as_deref() == Some("executing") {
            moving = true;
            last = Some(now);
        }
        if v.kind == "job" && v.status.as_deref() == Some("done") {
            break;
        }
        if moving && v.kind == "state" {
            if let Some(l) = last {
                seen.max_gap = seen.max_gap.max(now - l);
                seen.late += usize::from(now - l > Duration::from_millis(30));
            }
            last = Some(now);
            let sent = v.t_ms;
            if let Some(t) = sent {
                seen.delays.push(now_ms - t);
            }
            if let (Some(a), Some(b)) = (last_sent, sent) {
                seen.max_sent_gap = seen.max_sent_gap.max(b - a);
            }
            last_sent = sent;
            seen.count += 1;
        }
    }
    seen
}

/// The service's process: `reach serve` on a free loopback port, state in `dir`, until its
/// standard input closes.
fn service(dir: &str, speed: f64) {
    let mut config = Config::new(RobotInput::Preset("ur5".into()));
    config.state_dir = dir.into();
    config.listen = "127.0.0.1:0".parse().unwrap();
    config.speed = speed;
    let stdin_closed = async {
        let _ = tokio::task::spawn_blocking(|| std::io::stdin().lines().count()).await;
    };
    reach_serve::serve(&config, stdin_closed).expect("service");
}

/// Starts the service's process on a fresh state directory and reads where it listens.
fn start_service(dir: &std::path::Path, speed: f64) -> (Child, SocketAddr) {
    let _ = std::fs::remove_dir_all(dir);
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args(["--service", &dir.display().to_string(), &speed.to_string()])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("start the service");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).expect("the service's first line");
    let addr = line.split("http://").nth(1).and_then(|s| s.split_whitespace().next()).expect("listening on");
    (child, addr.parse().expect("address"))
}

/// Closes the service's standard input (it shuts down) and removes its state.
fn stop_service(mut child: Child, dir: &std::path::Path) {
    drop(child.stdin.take());
    let _ = child.wait();
    let _ = std::fs::remove_dir_all(dir);
}

fn post(addr: SocketAddr, body: &str) -> Value {
    let mut r =
        ureq::post(format!("http://{addr}/jobs")).content_type("application/json").send(body).expect("POST /jobs");
    serde_json::from_str(&r.body_mut().read_to_string().unwrap()).unwrap()
}

fn get(addr: SocketAddr, path: &str) -> Value {
    let mut r = ureq::get(format!("http://{addr}{path}")).call().expect("GET");
    serde_json::from_str(&r.body_mut().with_config().limit(1 << 30).read_to_string().unwrap()).unwrap()
}
