//! Benchmark (not a test): N WebSocket clients watch one long move; each counts the joint
//! states it receives while the arm moves, the largest gap between two of them as received,
//! and the largest gap between their send times (`t_ms`, stamped by the service's publisher):
//! the first includes the clients' own scheduling on the shared cores, the second is the
//! service's; and the delivery delay of every state (receipt minus send stamp). Then J jobs are queued at once and must run in submission order.
//!
//! `cargo run --release -p reach-serve --example ws_clients -- [CLIENTS] [SECONDS] [JOBS]`
//! (defaults 100, 60, 1000).

use std::time::{Duration, Instant};

use reach::jobs::RobotInput;
use reach_serve::{Config, Service};
use serde_json::Value;

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let clients = args.first().map_or(100, |&v| v as usize);
    let seconds = args.get(1).copied().unwrap_or(60.0);
    let jobs = args.get(2).map_or(1000, |&v| v as usize);
    let dir = std::env::temp_dir().join(format!("reach-ws-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut config = Config::new(RobotInput::Preset("ur5".into()));
    config.state_dir = dir.clone();
    let service = Service::open(&config).expect("service");
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).unwrap();
    let addr = listener.local_addr().unwrap();
    let router = service.router();
    runtime.spawn(async move { axum::serve(listener, router).await });

    let watchers: Vec<_> = (0..clients)
        .map(|_| {
            let (mut ws, _) = tungstenite::connect(format!("ws://{addr}/ws")).expect("connect");
            std::thread::spawn(move || {
                let (mut count, mut max_gap, mut last, mut moving) = (0usize, Duration::ZERO, None::<Instant>, false);
                let (mut last_sent, mut max_sent_gap, mut late) = (None::<i64>, 0i64, 0usize);
                let mut delays: Vec<i64> = Vec::new();
                loop {
                    let Ok(message) = ws.read() else { break };
                    let Ok(text) = message.to_text() else { continue };
                    let v: Value = serde_json::from_str(text).unwrap_or(Value::Null);
                    if v["type"] == "job" && v["status"] == "executing" {
                        moving = true;
                        last = Some(Instant::now());
                    }
                    if v["type"] == "job" && v["status"] == "done" {
                        break;
                    }
                    if moving && v["type"] == "state" {
                        let now = Instant::now();
                        if let Some(l) = last {
                            max_gap = max_gap.max(now - l);
                            late += usize::from(now - l > Duration::from_millis(30));
                        }
                        last = Some(now);
                        let sent = v["t_ms"].as_i64();
                        if let Some(t) = sent {
                            delays.push(reach_serve::db::now_ms() - t);
                        }
                        if let (Some(a), Some(b)) = (last_sent, sent) {
                            max_sent_gap = max_sent_gap.max(b - a);
                        }
                        last_sent = sent;
                        count += 1;
                    }
                }
                (count, max_gap, max_sent_gap, late, delays)
            })
        })
        .collect();
    let body = format!(r#"{{"kind": "move", "to_deg": [90, -45, 30, 0, 0, 10], "duration_s": {seconds}}}"#);
    post(addr, &body);
    let results: Vec<(usize, Duration, i64, usize, Vec<i64>)> =
        watchers.into_iter().map(|w| w.join().unwrap()).collect();
    let mut delays: Vec<i64> = results.iter().flat_map(|r| r.4.iter().copied()).collect();
    delays.sort_unstable();
    let at = |p: f64| delays.get(((delays.len().saturating_sub(1)) as f64 * p) as usize).copied().unwrap_or(0);
    let min_count = results.iter().map(|r| r.0).min().unwrap_or(0);
    let worst_gap = results.iter().map(|r| r.1).max().unwrap_or_default();
    let worst_sent_gap = results.iter().map(|r| r.2).max().unwrap_or_default();
    let late: usize = results.iter().map(|r| r.3).sum();
    let total: usize = results.iter().map(|r| r.0).sum();
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

    // J jobs queued at once, run in order (fast: a 10 ms move each at 100x).
    drop(service);
    let _ = std::fs::remove_dir_all(&dir);
    config.speed = 100.0;
    let service = Service::open(&config).expect("service");
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).unwrap();
    let addr = listener.local_addr().unwrap();
    let router = service.router();
    runtime.spawn(async move { axum::serve(listener, router).await });
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
    drop(service);
    let _ = std::fs::remove_dir_all(&dir);
}

fn post(addr: std::net::SocketAddr, body: &str) -> Value {
    let mut r =
        ureq::post(format!("http://{addr}/jobs")).content_type("application/json").send(body).expect("POST /jobs");
    serde_json::from_str(&r.body_mut().read_to_string().unwrap()).unwrap()
}

fn get(addr: std::net::SocketAddr, path: &str) -> Value {
    let mut r = ureq::get(format!("http://{addr}{path}")).call().expect("GET");
    serde_json::from_str(&r.body_mut().with_config().limit(1 << 30).read_to_string().unwrap()).unwrap()
}
