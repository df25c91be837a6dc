// The C-space panel beside the 3-D view: a two-joint section of the configuration space
// (`report.cspace`, classified by the library as `reach cspace` does): one cell per grid node,
// coloured by its class, the motion's path in the two joints and the state shown as a dot.
import { el } from './dom.js';

/** Cell colours by class: allowed, outside limits, tool outside zone, self-collision, obstacle. */
export const CLASS_COLORS = [
  [255, 255, 255],
  [158, 158, 158],
  [129, 199, 132],
  [255, 183, 77],
  [229, 57, 53],
];
const CLASS_NAMES = ['allowed', 'outside limits', 'tool outside zone', 'self-collision', 'obstacle'];
const PAD = { l: 36, r: 6, t: 6, b: 30 };

/** Cell edges of grid values: halfway between neighbours, half a gap beyond the ends. */
function edges(values) {
  const n = values.length;
  if (n === 1) return [values[0] - 0.5, values[0] + 0.5];
  const e = [values[0] - (values[1] - values[0]) / 2];
  for (let i = 0; i + 1 < n; i++) e.push((values[i] + values[i + 1]) / 2);
  e.push(values[n - 1] + (values[n - 1] - values[n - 2]) / 2);
  return e;
}

export class CspacePanel {
  constructor(canvas, caption, report) {
    this.canvas = canvas;
    this.report = report;
    const c = report.cspace;
    this.c = c;
    const [ex, ey] = c.axes_deg.map(edges);
    const w = canvas.width;
    const h = canvas.height;
    this.x = (v) => PAD.l + ((v - ex[0]) / (ex[ex.length - 1] - ex[0])) * (w - PAD.l - PAD.r);
    this.y = (v) => h - PAD.b - ((v - ey[0]) / (ey[ey.length - 1] - ey[0])) * (h - PAD.t - PAD.b);
    // The grid layer, drawn once: cells on whole pixels so that each centre has its class's colour.
    this.grid = document.createElement('canvas');
    this.grid.width = w;
    this.grid.height = h;
    const g = this.grid.getContext('2d');
    const nx = c.axes_deg[0].length;
    const ny = c.axes_deg[1].length;
    this.centres = [];
    for (let i = 0; i < nx; i++) {
      const x0 = Math.round(this.x(ex[i]));
      const x1 = Math.round(this.x(ex[i + 1]));
      for (let k = 0; k < ny; k++) {
        const y0 = Math.round(this.y(ey[k + 1]));
        const y1 = Math.round(this.y(ey[k]));
        const cls = c.classes[i * ny + k];
        g.fillStyle = `rgb(${CLASS_COLORS[cls].join(',')})`;
        g.fillRect(x0, y0, x1 - x0, y1 - y0);
        this.centres.push([Math.floor((x0 + x1) / 2), Math.floor((y0 + y1) / 2)]);
      }
    }
    g.strokeStyle = '#bbb';
    g.strokeRect(PAD.l - 0.5, PAD.t - 0.5, w - PAD.l - PAD.r + 1, h - PAD.t - PAD.b + 1);
    g.fillStyle = '#333';
    g.font = '11px sans-serif';
    const [a, b] = c.joints.map((j) => report.joint_names[j - 1]);
    g.fillText(`${ex[0].toFixed(0)}`, PAD.l, h - PAD.b + 12);
    g.fillText(`${ex[ex.length - 1].toFixed(0)}`, w - PAD.r - 24, h - PAD.b + 12);
    g.fillText(`${a} →`, PAD.l + (w - PAD.l - PAD.r) / 2 - 20, h - PAD.b + 12);
    g.fillText(`${ey[ey.length - 1].toFixed(0)}`, 2, PAD.t + 10);
    g.fillText(`${ey[0].toFixed(0)}`, 2, h - PAD.b);
    g.fillText(`${b} ↑`, 2, PAD.t + (h - PAD.t - PAD.b) / 2);
    // The path: every state's two joint values.
    this.path = report.states.map((s) => [this.x(s.q_deg[c.joints[0] - 1]), this.y(s.q_deg[c.joints[1] - 1])]);
    const others = report.joint_names
      .map((n, j) => (c.joints.includes(j + 1) ? null : `${n} = ${c.through_q_deg[j].toFixed(1)}`))
      .filter((t) => t);
    const forbidden = c.counts.nodes - c.counts.allowed;
    caption.textContent =
      `C-space section ${a} × ${b}` +
      (others.length ? ` at ${others.join(', ')}` : '') +
      `, step ${c.step_deg}°: ${forbidden} of ${c.counts.nodes} cells forbidden` +
      (c.off_section_deg > 0 ? `; the motion leaves the section by up to ${c.off_section_deg.toFixed(2)}` : '') +
      '.';
    const legend = el('div', {}, caption);
    CLASS_NAMES.forEach((name, k) => {
      const swatch = el('span', { textContent: '■' }, legend);
      swatch.style.color = `rgb(${CLASS_COLORS[k].join(',')})`;
      swatch.style.textShadow = '0 0 1px #000';
      el('span', { textContent: ` ${name}  ` }, legend);
    });
  }

  /** Draws the grid, the path and the state `index` as a dot. */
  draw(index) {
    const g = this.canvas.getContext('2d');
    g.clearRect(0, 0, this.canvas.width, this.canvas.height);
    g.drawImage(this.grid, 0, 0);
    g.strokeStyle = '#6a1b9a';
    g.lineWidth = 2;
    g.beginPath();
    this.path.forEach(([x, y], k) => (k ? g.lineTo(x, y) : g.moveTo(x, y)));
    g.stroke();
    const [x, y] = this.path[index];
    g.fillStyle = '#000';
    g.beginPath();
    g.arc(x, y, 4, 0, 2 * Math.PI);
    g.fill();
  }

  /** What the panel drew (for tests): `cells`, `forbidden` (cells whose centre shows another
   * colour than the allowed one), `pathPoints` (vertices of the path) and `pathDrawn` (vertices
   * whose pixel the path or the dot changed over the grid). */
  summary() {
    const data = this.grid.getContext('2d').getImageData(0, 0, this.grid.width, this.grid.height).data;
    const shown = this.canvas.getContext('2d').getImageData(0, 0, this.canvas.width, this.canvas.height).data;
    let pathDrawn = 0;
    for (const [x, y] of this.path) {
      const p = 4 * (Math.floor(y) * this.grid.width + Math.floor(x));
      if ([0, 1, 2].some((c) => data[p + c] !== shown[p + c])) pathDrawn += 1;
    }
    let forbidden = 0;
    const allowed = CLASS_COLORS[0];
    for (const [x, y] of this.centres) {
      const p = 4 * (y * this.grid.width + x);
      if (data[p] !== allowed[0] || data[p + 1] !== allowed[1] || data[p + 2] !== allowed[2]) forbidden += 1;
    }
    return { cells: this.centres.length, forbidden, pathPoints: this.path.length, pathDrawn };
  }
}
