//! The HTTP and WebSocket API (described in `docs/openapi.json`, served at
//! `GET /openapi.json`).

use std::sync::Arc;

use axum::body::Bytes;
use axum::extract::rejection::BytesRejection;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{DefaultBodyLimit, Path, Query, Request, State};
use axum::http::{HeaderValue, Method, StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{delete, get, post};
use axum::{Json, Router};
use serde_json::{Value, json};
use tokio::sync::broadcast::error::RecvError;

use crate::db::JobStatus;
use crate::error::ApiError;
use crate::intake;
use crate::service::{Control, MAX_BODY_BYTES, MAX_QUEUED_JOBS, Shared, lock};

/// The OpenAPI description of this API.
pub const OPENAPI: &str = include_str!("../../../docs/openapi.json");

/// Jobs `GET /jobs` lists by default (the newest ones; reports make a job large).
const LIST_DEFAULT: i64 = 100;

/// Most jobs `GET /jobs?limit=N` lists.
const LIST_LIMIT: i64 = 10_000;

type AppState = State<Arc<Shared>>;

/// The service's routes, with the body limit, the token check and CORS.
pub fn router(shared: Arc<Shared>) -> Router {
    let mut router = Router::new()
        .route("/", get(live_page))
        .route("/favicon.ico", get(|| async { StatusCode::NO_CONTENT }))
        .route("/state", get(state))
        .route("/jobs", get(list_jobs).post(submit))
        .route("/jobs/{id}", get(job))
        .route("/jobs/{id}/choose", post(choose))
        .route("/stop", post(stop))
        .route("/estop", post(estop))
        .route("/resume", post(resume))
        .route("/scene/obstacles", post(add_obstacle))
        .route("/scene/obstacles/{name}", delete(remove_obstacle))
        .route("/sense", post(sense))
        .route("/ws", get(ws))
        .route("/openapi.json", get(openapi))
        .route("/schemas/{name}", get(schema))
        .fallback(not_found)
        .layer(middleware::from_fn_with_state(shared.clone(), guard))
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES));
    if let Some(origin) = shared.cors.as_deref().and_then(|o| HeaderValue::from_str(o).ok()) {
        router = router.layer(
            tower_http::cors::CorsLayer::new()
                .allow_origin(origin)
                .allow_methods([Method::GET, Method::POST, Method::DELETE])
                .allow_headers([header::AUTHORIZATION, header::CONTENT_TYPE]),
        );
    }
    router.with_state(shared)
}

/// Refuses bodies announced beyond [`MAX_BODY_BYTES`] (413, before reading them), requests from a browser page of another origin than `--cors` (403: a page must not
/// drive the arm through the loopback service), and, beyond loopback, requests without the
/// token (401; the WebSocket may give it as `?token=`).
async fn guard(State(shared): AppState, request: Request, next: Next) -> Response {
    // A body announced larger than the limit is refused before it is read.
    let announced = request.headers().get(header::CONTENT_LENGTH).and_then(|v| v.to_str().ok()?.parse::<u64>().ok());
    if announced.is_some_and(|n| n > MAX_BODY_BYTES as u64) {
        return too_large().into_response();
    }
    if let Some(origin) = request.headers().get(header::ORIGIN)
        && shared.cors.as_deref().is_none_or(|allowed| origin.as_bytes() != allowed.as_bytes())
        && !same_origin(origin.as_bytes(), request.headers().get(header::HOST).map(HeaderValue::as_bytes))
    {
        return ApiError {
            status: StatusCode::FORBIDDEN,
            message: format!(
                "requests from the browser origin `{}` are refused; start the service with --cors ORIGIN to allow one",
                origin.to_str().unwrap_or("?")
            ),
        }
        .into_response();
    }
    if request.headers().get_all(header::HOST).iter().nth(1).is_some() {
        // Two Host headers: which one a proxy or the router reads is not defined.
        return ApiError::bad_request("the request has more than one Host header").into_response();
    }
    if shared.token.is_none()
        && let Some(host) = request.headers().get(header::HOST)
        && !loopback_host(host.to_str().unwrap_or(""))
    {
        // A page of another site that resolves its name to 127.0.0.1 (DNS rebinding) sends its
        // own name: the loopback service answers only to loopback names.
        return ApiError {
            status: StatusCode::FORBIDDEN,
            message: format!(
                "requests for host `{}` are refused: the service listens on loopback; call it as localhost or 127.0.0.1",
                host.to_str().unwrap_or("?")
            ),
        }
        .into_response();
    }
    if let Some(token) = &shared.token {
        let path = request.uri().path();
        let open = is_open(request.method(), path);
        let bearer = request
            .headers()
            .get(header::AUTHORIZATION)
            .and_then(|v| v.to_str().ok())
            .and_then(|v| v.strip_prefix("Bearer "))
            .map(str::trim);
        // A browser cannot set headers when it opens a page or a WebSocket: there (only) the
        // token may be a query.
        let query = QUERY_TOKEN_PATHS
            .contains(&path)
            .then(|| request.uri().query().and_then(|q| q.split('&').find_map(|kv| kv.strip_prefix("token="))))
            .flatten();
        let given = bearer.or(query);
        if !open && !given.is_some_and(|g| crate::auth::same_token(g, token)) {
            return ApiError::unauthorized().into_response();
        }
    }
    next.run(request).await
}

/// Whether a request needs no token: the API's descriptions, which hold no state
/// (`GET /openapi.json`, `GET /schemas/{name}`). `docs/openapi.json` marks exactly these
/// `security: []` (a test holds the two together).
fn is_open(method: &Method, path: &str) -> bool {
    method == Method::GET && (path == "/openapi.json" || path.starts_with("/schemas/"))
}

/// The routes that may carry the token as the query `?token=` (a browser cannot set headers
/// when it opens a page or a WebSocket); `docs/openapi.json` gives exactly these a `token`
/// query parameter.
const QUERY_TOKEN_PATHS: [&str; 2] = ["/", "/ws"];

/// Whether a browser's `Origin` is the service itself (`http://` + the request's `Host`): the
/// live page at `/` calls the API it was served by. (On loopback the `Host` is checked to be
/// a loopback name first, so another site cannot pass for the service.)
fn same_origin(origin: &[u8], host: Option<&[u8]>) -> bool {
    host.is_some_and(|h| origin.strip_prefix(b"http://") == Some(h))
}

/// Whether a `Host` header is exactly a loopback name or address: `localhost` (any case), an
/// IPv4 loopback address (`127.x.x.x`, written in full) or `[::1]`, optionally followed by `:`
/// and a port of 1 to 5 digits; nothing else (`[::1].evil.com`, `localhost.evil.com` and
/// `127.0.0.1:80x` are not loopback).
fn loopback_host(host: &str) -> bool {
    let (name_ok, port) = if let Some(rest) = host.strip_prefix('[') {
        let Some((inner, tail)) = rest.split_once(']') else { return false };
        (inner.parse::<std::net::Ipv6Addr>().is_ok_and(|ip| ip.is_loopback()), tail)
    } else {
        let (name, tail) = host.find(':').map_or((host, ""), |i| host.split_at(i));
        let ok = name.eq_ignore_ascii_case("localhost")
            || name.parse::<std::net::Ipv4Addr>().is_ok_and(|ip| ip.is_loopback());
        (ok, tail)
    };
    let port_ok = port.is_empty()
        || port.strip_prefix(':').is_some_and(|p| (1..=5).contains(&p.len()) && p.bytes().all(|b| b.is_ascii_digit()));
    name_ok && port_ok
}

/// 413.
fn too_large() -> ApiError {
    ApiError {
        status: StatusCode::PAYLOAD_TOO_LARGE,
        message: format!("the request body is larger than the limit of {MAX_BODY_BYTES} bytes"),
    }
}

/// A body that could not be read: 413 beyond the limit, else 400.
fn body_error(rejection: &BytesRejection) -> ApiError {
    if rejection.status() == StatusCode::PAYLOAD_TOO_LARGE {
        too_large()
    } else {
        ApiError::bad_request(rejection.body_text())
    }
}

/// Runs `work` on the blocking pool. The database's lock and the live state's are shared with
/// the executor, which holds them through a commit (an fsync); the async workers, which also
/// feed the WebSocket streams, must never wait for them.
async fn blocking<T: Send + 'static>(
    shared: &Arc<Shared>,
    work: impl FnOnce(&Shared) -> Result<T, ApiError> + Send + 'static,
) -> Result<T, ApiError> {
    let shared = shared.clone();
    tokio::task::spawn_blocking(move || work(&shared)).await.map_err(|e| ApiError::internal(e.to_string()))?
}

/// The number of queued jobs.
async fn queued(shared: &Arc<Shared>) -> Result<i64, ApiError> {
    blocking(shared, |s| Ok(lock(&s.db).queued_count()?)).await
}

async fn not_found() -> ApiError {
    ApiError::not_found("no such endpoint; see GET /openapi.json")
}

async fn openapi() -> impl IntoResponse {
    ([(header::CONTENT_TYPE, "application/json")], OPENAPI)
}

/// The library's generated JSON Schemas (as in `docs/schemas/`), by file name.
async fn schema(Path(name): Path<String>) -> Result<Json<Value>, ApiError> {
    let stem = name.strip_suffix(".schema.json").unwrap_or(&name);
    reach::jobs::schemas()
        .into_iter()
        .find(|(n, _)| *n == stem)
        .map(|(_, s)| Json(s))
        .ok_or_else(|| ApiError::not_found(format!("no schema `{name}`")))
}

/// `GET /`: the 3-D viewer (`reach view`'s page) showing the arm where it is and the scene,
/// following the service live: joint states over the WebSocket, the operator's questions
/// answered with buttons.
async fn live_page(State(shared): AppState) -> Result<Response, ApiError> {
    let html = blocking(&shared, |shared| {
        let q = shared.q_deg(&lock(&shared.live).steps);
        let scene = lock(&shared.db).scene()?;
        let request = reach::jobs::ViewRequest {
            q: Some(reach::jobs::Joints::Deg(q)),
            scene,
            ..reach::jobs::ViewRequest::default()
        };
        let report = reach::jobs::view::view(&shared.robot, &request).map_err(|e| ApiError::internal(e.to_string()))?;
        let json = serde_json::to_string(&report).unwrap_or_default();
        Ok(reach::jobs::view::page(&report.robot, &json, true))
    })
    .await?;
    Ok(([(header::CONTENT_TYPE, "text/html; charset=utf-8")], html).into_response())
}

async fn state(State(shared): AppState) -> Result<Json<Value>, ApiError> {
    let queued = queued(&shared).await?;
    let mut state = blocking(&shared, |s| Ok(s.state(&lock(&s.live)))).await?;
    state["drives"] = shared.drives();
    state["speed"] = json!(shared.speed);
    state["queued"] = json!(queued);
    Ok(Json(state))
}

/// A job as the API shows it; one waiting for the operator adds its `questions`.
fn job_json(row: &crate::db::JobRow) -> Value {
    let questions = (row.status == JobStatus::WaitingOperator)
        .then(|| {
            let request = serde_json::from_value(row.request.clone()).ok()?;
            let report = serde_json::from_value(row.report.clone()?).ok()?;
            Some(intake::questions(&request, &report))
        })
        .flatten();
    json!({
        "questions": questions,
        "id": row.id,
        "kind": row.kind,
        "status": row.status,
        "report": row.report,
        "segment": row.segment,
        "segments": row.segments,
        "message": row.message,
        "request": row.request,
        "created_ms": row.created_ms,
        "updated_ms": row.updated_ms,
    })
}

async fn list_jobs(
    State(shared): AppState,
    Query(q): Query<std::collections::HashMap<String, String>>,
) -> Result<Json<Value>, ApiError> {
    let limit = q.get("limit").and_then(|l| l.parse::<i64>().ok()).unwrap_or(LIST_DEFAULT).clamp(1, LIST_LIMIT);
    let rows = blocking(&shared, move |s| Ok(lock(&s.db).jobs(limit)?)).await?;
    Ok(Json(Value::Array(rows.iter().map(job_json).collect())))
}

async fn job(State(shared): AppState, Path(id): Path<String>) -> Result<Json<Value>, ApiError> {
    let missing = || ApiError::not_found(format!("no job `{id}`"));
    let n: i64 = id.parse().map_err(|_| missing())?;
    let row = blocking(&shared, move |s| Ok(lock(&s.db).job(n)?)).await?.ok_or_else(missing)?;
    Ok(Json(job_json(&row)))
}

/// `POST /jobs`: reads the request, plans it with the library (400 with the library's message
/// for bad input), and queues it — or records it `refused` with its report when the plan is
/// infeasible.
async fn submit(State(shared): AppState, body: Result<Bytes, BytesRejection>) -> Result<Response, ApiError> {
    let body = body.map_err(|e| body_error(&e))?;
    let submission = intake::parse_request(&body)?;
    let request = if submission.from_current {
        let q = blocking(&shared, |s| Ok(s.q_deg(&lock(&s.live).steps))).await?;
        intake::start_here(&submission.request, &q)
    } else {
        submission.request
    };
    if queued(&shared).await? >= MAX_QUEUED_JOBS {
        return Err(ApiError::conflict(format!("the queue is full ({MAX_QUEUED_JOBS} jobs); wait for it to drain")));
    }
    let (request, report) = plan(&shared, request).await?;
    let refusal = intake::refusal(&report);
    let asks = !intake::questions(&request, &report).is_empty();
    let (status, message) = match refusal {
        Some(why) => (JobStatus::Refused, Some(why)),
        None if asks => (
            JobStatus::WaitingOperator,
            Some("several configurations are feasible: answer with POST /jobs/{id}/choose (see `questions`)".into()),
        ),
        None => (JobStatus::Queued, None),
    };
    let kind = intake::kind_of(&request);
    let request = serde_json::to_value(&request).unwrap_or_default();
    let report = serde_json::to_value(&report).unwrap_or_default();
    let (from_current, note) = (submission.from_current, message.clone());
    let id = blocking(&shared, move |s| {
        let id = lock(&s.db).insert_job(&kind, &request, from_current, status, Some(&report), note.as_deref())?;
        s.job_event(id, status, note.as_deref());
        s.wake.notify_all();
        Ok(id)
    })
    .await?;
    let body = json!({"id": id, "status": status, "message": message});
    Ok((StatusCode::CREATED, Json(body)).into_response())
}

/// Plans `request` with the library on the blocking pool, at most [`crate::service::MAX_PLANNING`] at once
/// (the others wait their turn): 400 with the library's message for bad input.
async fn plan(
    shared: &Arc<Shared>,
    request: reach::jobs::Request,
) -> Result<(reach::jobs::Request, reach::jobs::Report), ApiError> {
    let _permit = shared.planning.acquire().await.map_err(|e| ApiError::internal(e.to_string()))?;
    blocking(shared, move |s| {
        let report = intake::plan(&s.robot, &request)?;
        intake::require_storable(&report)?;
        Ok((request, report))
    })
    .await
}

/// 409: job `n` is `status`, no longer waiting for the operator.
fn not_waiting(n: i64, status: JobStatus) -> ApiError {
    ApiError::conflict(format!("job {n} is {}, not waiting for the operator", status.as_str()))
}

/// The body of `POST /jobs/{id}/choose`: the library's per-interval choices.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Answer {
    choices: Vec<reach::jobs::motion::IntervalChoice>,
}

/// `POST /jobs/{id}/choose`: the operator's answer to a job waiting for it (seed 003's
/// dialogue): `{"choices": [{"interval": 1, "configuration": "…"}]}`, labels from the job's
/// `questions`. The move is re-planned with them (400 with the library's message when a
/// choice is not feasible, or the motion with them is not) and queued; 409 when the job no
/// longer waits (it ran, or the criterion answered after the timeout).
async fn choose(
    State(shared): AppState,
    Path(id): Path<String>,
    body: Result<Bytes, BytesRejection>,
) -> Result<Json<Value>, ApiError> {
    let body = body.map_err(|e| body_error(&e))?;
    let missing = || ApiError::not_found(format!("no job `{id}`"));
    let n: i64 = id.parse().map_err(|_| missing())?;
    let answer: Answer =
        serde_json::from_slice(&body).map_err(|e| ApiError::bad_request(format!("the answer: {e}")))?;
    let row = blocking(&shared, move |s| Ok(lock(&s.db).job(n)?)).await?.ok_or_else(missing)?;
    if row.status != JobStatus::WaitingOperator {
        return Err(not_waiting(n, row.status));
    }
    let request: reach::jobs::Request =
        serde_json::from_value(row.request.clone()).map_err(|e| ApiError::internal(format!("stored request: {e}")))?;
    let (request, report) = plan(&shared, intake::with_choices(&request, &answer.choices)).await?;
    if let Some(why) = intake::refusal(&report) {
        return Err(ApiError::bad_request(format!("with these choices the motion is infeasible: {why}")));
    }
    let chosen: Vec<String> =
        answer.choices.iter().map(|c| format!("interval {}: {}", c.interval, c.configuration)).collect();
    let message = format!("the operator chose {}", chosen.join(", "));
    let (rq, rp) =
        (serde_json::to_value(&request).unwrap_or_default(), serde_json::to_value(&report).unwrap_or_default());
    blocking(&shared, move |s| {
        let db = lock(&s.db);
        if !db.answer(n, &rq, &rp, &message)? {
            return Err(not_waiting(n, db.job(n)?.map_or(JobStatus::Queued, |r| r.status)));
        }
        drop(db);
        s.job_event(n, JobStatus::Queued, Some(&message));
        s.wake.notify_all();
        Ok(Json(json!({"id": n, "status": JobStatus::Queued, "message": message, "report": rp})))
    })
    .await
}

/// Pauses the queue and asks the running job (if any) to stop.
fn halt(shared: &Shared, control: Control) -> Result<Json<Value>, ApiError> {
    let mut live = lock(&shared.live);
    live.paused = true;
    // The executor is told first (an estop must not wait for the database), and a stop never
    // softens an estop already asked for.
    if live.job.is_some() {
        live.control = Some(if live.control == Some(Control::Estop) { Control::Estop } else { control });
    }
    shared.wake.notify_all();
    lock(&shared.db).set_paused(true)?;
    let state = shared.state(&live);
    drop(live);
    let what = if control == Control::Stop { "stop" } else { "estop" };
    let _ = lock(&shared.db).add_event(None, what, "queue paused until POST /resume");
    shared.publish(&json!({"type": what}));
    Ok(Json(state))
}

async fn stop(State(shared): AppState) -> Result<Json<Value>, ApiError> {
    blocking(&shared, |s| halt(s, Control::Stop)).await
}

async fn estop(State(shared): AppState) -> Result<Json<Value>, ApiError> {
    blocking(&shared, |s| halt(s, Control::Estop)).await
}

/// `POST /scene/obstacles`: one obstacle in the scene file's format as JSON (`{"name",
/// "shape", ...}`, in the stored scene's units; metres for a service started without a
/// scene), appended to the scene and checked by the library's scene parser (400 with its
/// message). Jobs that start afterwards must be proven clear of it; the one executing
/// re-checks the rest of its motion (and detours or stops).
async fn add_obstacle(State(shared): AppState, body: Result<Bytes, BytesRejection>) -> Result<Response, ApiError> {
    let body = body.map_err(|e| body_error(&e))?;
    let value: Value =
        serde_json::from_slice(&body).map_err(|e| ApiError::bad_request(format!("the body is not JSON: {e}")))?;
    if !value.is_object() {
        return Err(ApiError::bad_request(
            "an obstacle is a JSON object: {\"name\", \"shape\", ...} (docs/scene-format.md)",
        ));
    }
    let obstacles = blocking(&shared, move |s| append_obstacle(s, &value, None)).await?;
    Ok((StatusCode::CREATED, Json(json!({"obstacles": obstacles}))).into_response())
}

/// Appends one obstacle (scene-file format as JSON) to the stored scene, checked by the
/// library's parser; `metres`: the names of the obstacle's length fields given in metres, scaled
/// to the scene's length unit. Returns the number of obstacles in the scene now.
fn append_obstacle(shared: &Shared, value: &Value, metres: Option<&[&str]>) -> Result<usize, ApiError> {
    let db = lock(&shared.db);
    // A service started without a scene gets one in metres and degrees.
    let old = db.scene()?.unwrap_or_else(|| "length_unit = \"m\"\nangle_unit = \"deg\"\n".to_string());
    let mut value = value.clone();
    if let Some(fields) = metres {
        let in_mm = toml::from_str::<toml::Table>(&old)
            .ok()
            .is_some_and(|t| t.get("length_unit").and_then(toml::Value::as_str) == Some("mm"));
        let scale = if in_mm { 1000.0 } else { 1.0 };
        for field in fields {
            value[*field] = scale_numbers(&value[*field], scale);
        }
    }
    let table = toml::to_string(&value).map_err(|e| ApiError::bad_request(format!("obstacle: {e}")))?;
    let text = format!("{old}\n[[obstacles]]\n{table}");
    let scene = reach::jobs::world::parse_scene(&text).map_err(|e| ApiError::bad_request(e.to_string()))?;
    crate::service::require_keepable(&shared.robot, &scene).map_err(ApiError::bad_request)?;
    if let Some((last, before)) = scene.obstacles.split_last()
        && before.iter().any(|o| o.name == last.name)
    {
        return Err(ApiError::conflict(format!(
            "the scene already has an obstacle named `{}`; give another name, or remove it first (DELETE /scene/obstacles/{{name}})",
            last.name
        )));
    }
    let name = value["name"].as_str().unwrap_or("");
    let obstacles = store_scene(shared, &db, &text, scene, "obstacle", name)?;
    drop(db);
    // The job executing re-checks the rest of its motion against the new scene.
    let mut live = lock(&shared.live);
    if live.job.is_some() {
        live.scene_changed = true;
        shared.wake.notify_all();
    }
    Ok(obstacles)
}

/// Stores a changed scene (its text in the database, the parsed scene for the executor), and
/// journals and announces the change (`event`: `obstacle` or `obstacle_removed`, of obstacle
/// `name`). The caller holds the database lock, so concurrent changes keep their order.
/// Returns the number of obstacles in the scene now.
fn store_scene(
    shared: &Shared,
    db: &crate::db::Db,
    text: &str,
    scene: reach::world::Scene,
    event: &str,
    name: &str,
) -> Result<usize, ApiError> {
    db.set_scene(text)?;
    let obstacles = scene.obstacles.len();
    *shared.scene.write().unwrap_or_else(std::sync::PoisonError::into_inner) = Some(scene);
    let _ = db.add_event(None, event, name);
    shared.publish(&json!({"type": event, "name": name, "obstacles": obstacles}));
    Ok(obstacles)
}

/// `DELETE /scene/obstacles/{name}`: removes the obstacle of that name from the stored scene
/// (404 when there is none; every obstacle of that name in a scene stored before names were
/// unique). Journalled and announced like an addition; the obstacles left keep their names.
/// Fewer obstacles only make a proven-clear motion clearer, so the job executing goes on.
async fn remove_obstacle(State(shared): AppState, Path(name): Path<String>) -> Result<Json<Value>, ApiError> {
    blocking(&shared, move |s| {
        let db = lock(&s.db);
        let missing = |names: &[&str]| {
            ApiError::not_found(format!(
                "no obstacle `{name}` in the scene (its obstacles: {})",
                if names.is_empty() { "none".to_string() } else { names.join(", ") }
            ))
        };
        let Some(old) = db.scene()? else { return Err(missing(&[])) };
        if reach::jobs::world::is_moveit_scene(&old) {
            return Err(ApiError::bad_request(
                "the service's scene is a MoveIt planning scene (given with --scene): edit that file and restart",
            ));
        }
        let scene = reach::jobs::world::parse_scene(&old).map_err(|e| ApiError::internal(e.to_string()))?;
        let mut table: toml::Table =
            toml::from_str(&old).map_err(|e| ApiError::internal(format!("stored scene: {e}")))?;
        let Some(toml::Value::Array(entries)) = table.get_mut("obstacles") else { return Err(missing(&[])) };
        // Unnamed entries are named by their place: they keep the name they had.
        for (entry, obstacle) in entries.iter_mut().zip(&scene.obstacles) {
            if let Some(t) = entry.as_table_mut() {
                t.entry("name").or_insert_with(|| obstacle.name.clone().into());
            }
        }
        let before = entries.len();
        entries.retain(|e| e.get("name").and_then(toml::Value::as_str) != Some(name.as_str()));
        if entries.len() == before {
            let names: Vec<&str> = scene.obstacles.iter().map(|o| o.name.as_str()).collect();
            return Err(missing(&names));
        }
        let text = toml::to_string(&table).map_err(|e| ApiError::internal(e.to_string()))?;
        let scene = reach::jobs::world::parse_scene(&text).map_err(|e| ApiError::internal(e.to_string()))?;
        let obstacles = store_scene(s, &db, &text, scene, "obstacle_removed", &name)?;
        Ok(Json(json!({"removed": name, "obstacles": obstacles})))
    })
    .await
}

/// What the service's scene is, for the refusal of moving obstacles: the service keeps no
/// clock for them (an obstacle's time 0 would be each job's start).
pub const FIXED_SCENE: &str = "the service's scene (obstacles stay where they are put)";

/// `value` with every number multiplied by `scale` (numbers and arrays of numbers).
fn scale_numbers(value: &Value, scale: f64) -> Value {
    match value {
        Value::Number(n) => json!(n.as_f64().unwrap_or(f64::NAN) * scale),
        Value::Array(items) => Value::Array(items.iter().map(|v| scale_numbers(v, scale)).collect()),
        other => other.clone(),
    }
}

/// `POST /sense`: range readings (the library's sense request: seed 000's range finders in
/// the x–y plane of the robot's base frame) → the library's sense report. An obstacle located
/// without ambiguity joins the scene as a sphere about the estimate at z = 0 whose radius is
/// the estimate's uncertainty (the obstacle lies inside it with 99.73 % probability); jobs
/// that start afterwards must be proven clear of it. An ambiguous fit adds nothing (`added`
/// is `false`; the report says why). The job executing is re-planned around it when its rest
/// is not clear (as for `POST /scene/obstacles`).
async fn sense(State(shared): AppState, body: Result<Bytes, BytesRejection>) -> Result<Json<Value>, ApiError> {
    let body = body.map_err(|e| body_error(&e))?;
    let request: reach::jobs::world::sense::SenseRequest =
        serde_json::from_slice(&body).map_err(|e| ApiError::bad_request(format!("readings: {e}")))?;
    blocking(&shared, move |s| {
        let report =
            reach::jobs::world::sense::sense(&s.robot, &request).map_err(|e| ApiError::bad_request(e.to_string()))?;
        let added = match (report.ambiguous, report.uncertainty_m) {
            (false, Some(radius)) => {
                let [x, y] = report.obstacle_m;
                let name = format!("sensed {}", crate::db::now_ms());
                let obstacle = json!({"name": name, "shape": "sphere", "center": [x, y, 0.0], "radius": radius});
                Some(append_obstacle(s, &obstacle, Some(&["center", "radius"]))?)
            }
            _ => None,
        };
        Ok(Json(json!({"report": report, "added": added.is_some(), "obstacles": added})))
    })
    .await
}

/// Lets queued jobs run again; 409 while a job is still stopping.
async fn resume(State(shared): AppState) -> Result<Json<Value>, ApiError> {
    blocking(&shared, |shared| {
        let mut live = lock(&shared.live);
        if let Some(job) = live.job {
            return Err(ApiError::conflict(format!("job {job} is still running; resume once it has stopped")));
        }
        live.paused = false;
        lock(&shared.db).set_paused(false)?;
        shared.wake.notify_all();
        let state = shared.state(&live);
        drop(live);
        let _ = lock(&shared.db).add_event(None, "resume", "");
        shared.publish(&json!({"type": "resume"}));
        Ok(Json(state))
    })
    .await
}

async fn ws(State(shared): AppState, upgrade: WebSocketUpgrade) -> Response {
    upgrade.on_upgrade(move |socket| stream(shared, socket))
}

/// Sends the joint state now, then every state and job message as it is published.
async fn stream(shared: Arc<Shared>, mut socket: WebSocket) {
    let mut rx = shared.events.subscribe();
    let Ok(first) = blocking(&shared, |s| Ok(s.state_message(&lock(&s.live)).to_string())).await else { return };
    if socket.send(Message::text(first)).await.is_err() {
        return;
    }
    loop {
        tokio::select! {
            incoming = socket.recv() => match incoming {
                Some(Ok(Message::Close(_)) | Err(_)) | None => return,
                Some(Ok(_)) => {}
            },
            event = rx.recv() => match event {
                Ok(text) => {
                    if socket.send(Message::text(text.as_ref())).await.is_err() {
                        return;
                    }
                }
                Err(RecvError::Lagged(_)) => {}
                Err(RecvError::Closed) => return,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Method, OPENAPI, QUERY_TOKEN_PATHS, Value, is_open, loopback_host};

    #[test]
    fn the_token_rule_is_the_one_the_openapi_description_states() {
        let api: Value = serde_json::from_str(OPENAPI).unwrap();
        let paths = api["paths"].as_object().unwrap();
        for (path, item) in paths {
            let concrete = path.replace("{name}", "move.request.schema.json").replace("{id}", "1");
            for (method, op) in item.as_object().unwrap() {
                let m = Method::from_bytes(method.to_uppercase().as_bytes()).unwrap();
                let open = op.get("security").and_then(Value::as_array).is_some_and(Vec::is_empty);
                assert_eq!(open, is_open(&m, &concrete), "{method} {path}: `security: []` iff open");
                let query = op["parameters"]
                    .as_array()
                    .is_some_and(|ps| ps.iter().any(|p| p["name"] == "token" && p["in"] == "query"));
                assert_eq!(query, QUERY_TOKEN_PATHS.contains(&concrete.as_str()), "{method} {path}: ?token=");
            }
        }
    }

    #[test]
    fn only_loopback_names_are_loopback_hosts() {
        for host in
            ["localhost", "LOCALHOST:7878", "127.0.0.1", "127.0.0.1:7878", "127.1.2.3:80", "[::1]", "[::1]:7878"]
        {
            assert!(loopback_host(host), "{host}");
        }
        for host in ["evil.example", "evil.example:7878", "10.0.0.1:7878", "localhost.evil.example", "[::2]:7878", ""] {
            assert!(!loopback_host(host), "{host}");
        }
    }
}
