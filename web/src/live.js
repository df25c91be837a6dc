// Live mode of the page `reach serve` serves at `/` (marked `data-live` on its data): follows the
// service over its WebSocket — the arm moves with every joint-state message (the message's
// `view`: frames, tool and axes computed by the library), K-events are listed as they
// happen, and a job waiting for the operator (seed 003's dialogue) shows its questions with
// one button per feasible configuration, which answers with POST /jobs/{id}/choose.
// Beyond loopback the page is opened as `/?token=TOKEN`; the token goes with every call.

import { el } from './dom.js';

const MAX_LATENCIES = 10000;

export function startLive(viewer, side) {
  const token = new URLSearchParams(location.search).get('token');
  const auth = token ? { Authorization: `Bearer ${token}` } : {};
  const wsUrl =
    `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws` +
    (token ? `?token=${encodeURIComponent(token)}` : '');
  const panel = el('div', { id: 'reach-live' });
  side.insertBefore(panel, side.firstChild);
  const status = el('div', { id: 'reach-live-status', textContent: 'connecting…' }, panel);
  const questions = el('div', { id: 'reach-questions' }, panel);
  const log = el('div', { id: 'reach-live-events' }, panel);
  const latencies = [];
  const asked = new Map();
  let received = 0;
  let last = null;

  function note(text) {
    el('div', { textContent: text }, log);
    while (log.childNodes.length > 50) log.removeChild(log.firstChild);
  }

  function ask(job) {
    if (asked.has(job.id) || !Array.isArray(job.questions)) return;
    const box = el('div', { className: 'reach-question' }, questions);
    asked.set(job.id, box);
    el('div', { textContent: `Job ${job.id} waits for your choice:` }, box);
    for (const q of job.questions) {
      const line = el('div', { textContent: `interval ${q.interval} (${q.start_s.toFixed(2)}–${q.end_s.toFixed(2)} s): ` }, box);
      for (const label of q.alternatives) {
        const button = el('button', { textContent: label + (label === q.proposed ? ' (proposed)' : '') }, line);
        button.dataset.job = job.id;
        button.dataset.interval = q.interval;
        button.dataset.configuration = label;
        button.addEventListener('click', () => answer(job.id, q.interval, label, box));
      }
    }
  }

  async function answer(id, interval, configuration, box) {
    const body = JSON.stringify({ choices: [{ interval, configuration }] });
    const reply = await fetch(`/jobs/${id}/choose`, {
      method: 'POST',
      headers: { 'Content-Type': 'application/json', ...auth },
      body,
    });
    const json = await reply.json().catch(() => ({}));
    note(reply.ok ? `job ${id}: ${json.message}` : `job ${id}: ${json.error || reply.status}`);
    if (reply.ok) retire(id, box);
  }

  function retire(id, box) {
    (box || asked.get(id))?.remove();
    asked.delete(id);
  }

  async function pending() {
    const reply = await fetch('/jobs?limit=100', { headers: auth }).catch(() => null);
    if (!reply || !reply.ok) return;
    for (const job of await reply.json()) if (job.status === 'waiting_operator') ask(job);
  }

  let frame = 0;
  function drawLatest() {
    frame = 0;
    if (last.view) viewer.showLive(last.view);
    status.textContent = `${last.robot}: ${last.status}` + (last.job != null ? ` (job ${last.job})` : '');
  }

  function connect() {
    const ws = new WebSocket(wsUrl);
    ws.onopen = () => pending();
    ws.onmessage = (m) => {
      const msg = JSON.parse(m.data);
      if (msg.type === 'state') {
        received += 1;
        if (latencies.length < MAX_LATENCIES) latencies.push(Date.now() - msg.t_ms);
        last = msg;
        // Drawn once per animation frame, the latest state: a slow renderer never builds a
        // backlog of messages.
        if (!frame) frame = requestAnimationFrame(drawLatest);
      } else if (msg.type === 'job') {
        note(`job ${msg.id}: ${msg.status}${msg.message ? ' — ' + msg.message : ''}`);
        if (msg.status === 'waiting_operator') ask(msg);
        else if (asked.has(msg.id)) retire(msg.id);
      } else if (msg.type === 'event') {
        note(`${msg.t_s.toFixed(3)} s ${msg.code}: ${msg.message}`);
      } else {
        note(msg.type);
      }
    };
    ws.onclose = () => {
      status.textContent = 'disconnected; reconnecting…';
      setTimeout(connect, 1000);
    };
  }
  connect();

  return {
    received: () => received,
    latencies: () => latencies.slice(),
    lastState: () => last,
  };
}
