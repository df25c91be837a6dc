// The joint plot beside the 3-D view: q(t) of every joint on a 2-D canvas, with a cursor at
// the current time. Revolute joints in degrees on the left scale; prismatic joints (metres)
// are scaled to the same plot height and marked "(m)" in the legend.
//
// The legend below the plot is laid out by measured text width: entries fill a row and wrap
// to the next; a name wider than a whole row is cut with an ellipsis (the canvas's tooltip
// lists every full name). The canvas grows by the rows it needs, so entries never overlap.

const PALETTE = ['#d32f2f', '#1565c0', '#2e7d32', '#f9a825', '#6a1b9a', '#00838f', '#5d4037', '#c2185b'];
const FONT = '11px sans-serif';
const ROW = 13; // legend row height, px
const GAP = 10; // space between legend entries, px
const SWATCH = 10; // colour line before each entry, px
const PLOT_HEIGHT = 170; // the plot area and its scale, px, above the legend

/** `text` cut with an ellipsis to at most `width` pixels as `g` measures it. */
function fitText(g, text, width) {
  if (g.measureText(text).width <= width) return text;
  let lo = 0;
  let hi = text.length;
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (g.measureText(`${text.slice(0, mid)}…`).width <= width) lo = mid;
    else hi = mid - 1;
  }
  return `${text.slice(0, lo)}…`;
}

export class JointPlot {
  constructor(canvas, report) {
    this.canvas = canvas;
    this.report = report;
    const qs = report.states.flatMap((s) => s.q_deg);
    this.lo = Math.min(...qs);
    this.hi = Math.max(...qs);
    if (this.hi - this.lo < 1e-9) {
      this.lo -= 1;
      this.hi += 1;
    }
    this.t0 = report.states[0].t_s;
    this.t1 = report.states[report.states.length - 1].t_s;
    this.layoutLegend();
  }

  /** Places the legend entries in rows (`this.legend`: text, full name, box in canvas
   * pixels) and sizes the canvas to hold them. */
  layoutLegend() {
    const c = this.canvas;
    const g = c.getContext('2d');
    g.font = FONT;
    const left = 4;
    const right = c.width - 4;
    const names = this.report.joint_names.map((n, j) => `${n}${this.report.prismatic[j] ? ' (m)' : ''}`);
    const entries = [];
    let x = left;
    let row = 0;
    names.forEach((full, j) => {
      const text = fitText(g, full, right - left - SWATCH - 3);
      const width = SWATCH + 3 + g.measureText(text).width;
      if (x > left && x + width > right) {
        row += 1;
        x = left;
      }
      entries.push({ joint: j, name: full, text, x, row, width });
      x += width + GAP;
    });
    const rows = names.length ? row + 1 : 0;
    c.height = PLOT_HEIGHT + 22 + rows * ROW + 4;
    this.legendTop = PLOT_HEIGHT + 22;
    this.legend = entries.map((e) => ({ ...e, y: this.legendTop + e.row * ROW }));
    c.title = names.join('\n');
  }

  /** The legend as drawn: per joint its text, full name and box (canvas pixels, CSS-sized
   * canvas: x, y of the top left corner, width, height). */
  legendBoxes() {
    return this.legend.map((e) => ({ joint: e.joint, name: e.name, text: e.text, x: e.x, y: e.y, width: e.width, height: ROW }));
  }

  draw(t) {
    const c = this.canvas;
    const g = c.getContext('2d');
    const w = c.width;
    const pad = { l: 40, r: 8, t: 8 };
    const bottom = PLOT_HEIGHT;
    g.clearRect(0, 0, w, c.height);
    g.font = FONT;
    g.textBaseline = 'alphabetic';
    g.fillStyle = '#333';
    const span = this.t1 - this.t0 || 1;
    const x = (tt) => pad.l + ((tt - this.t0) / span) * (w - pad.l - pad.r);
    const y = (v) => bottom - ((v - this.lo) / (this.hi - this.lo)) * (bottom - pad.t);
    g.strokeStyle = '#bbb';
    g.strokeRect(pad.l, pad.t, w - pad.l - pad.r, bottom - pad.t);
    g.fillText(this.hi.toFixed(0), 2, pad.t + 10);
    g.fillText(this.lo.toFixed(0), 2, bottom);
    g.fillText(`${this.t0.toFixed(2)} s`, pad.l, bottom + 14);
    const end = `${this.t1.toFixed(2)} s`;
    g.fillText(end, w - pad.r - g.measureText(end).width, bottom + 14);
    const states = this.report.states;
    this.report.joint_names.forEach((name, j) => {
      g.strokeStyle = PALETTE[j % PALETTE.length];
      g.beginPath();
      states.forEach((s, k) => (k ? g.lineTo(x(s.t_s), y(s.q_deg[j])) : g.moveTo(x(s.t_s), y(s.q_deg[j]))));
      g.stroke();
    });
    g.textBaseline = 'middle';
    for (const e of this.legend) {
      const colour = PALETTE[e.joint % PALETTE.length];
      const mid = e.y + ROW / 2;
      g.strokeStyle = colour;
      g.lineWidth = 2;
      g.beginPath();
      g.moveTo(e.x, mid);
      g.lineTo(e.x + SWATCH, mid);
      g.stroke();
      g.lineWidth = 1;
      g.fillStyle = colour;
      g.fillText(e.text, e.x + SWATCH + 3, mid);
    }
    g.textBaseline = 'alphabetic';
    g.strokeStyle = '#000';
    g.beginPath();
    g.moveTo(x(t), pad.t);
    g.lineTo(x(t), bottom);
    g.stroke();
  }
}
