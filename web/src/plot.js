// The joint plot beside the 3-D view: q(t) of every joint on a 2-D canvas, with a cursor at
// the current time. Revolute joints in degrees on the left scale; prismatic joints (metres)
// are scaled to the same plot height and marked "(m)" in the legend.

const PALETTE = ['#d32f2f', '#1565c0', '#2e7d32', '#f9a825', '#6a1b9a', '#00838f', '#5d4037', '#c2185b'];

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
  }

  draw(t) {
    const c = this.canvas;
    const g = c.getContext('2d');
    const w = c.width;
    const h = c.height;
    const pad = { l: 40, r: 8, t: 8, b: 34 };
    g.clearRect(0, 0, w, h);
    g.font = '11px sans-serif';
    g.fillStyle = '#333';
    const span = this.t1 - this.t0 || 1;
    const x = (tt) => pad.l + ((tt - this.t0) / span) * (w - pad.l - pad.r);
    const y = (v) => h - pad.b - ((v - this.lo) / (this.hi - this.lo)) * (h - pad.t - pad.b);
    g.strokeStyle = '#bbb';
    g.strokeRect(pad.l, pad.t, w - pad.l - pad.r, h - pad.t - pad.b);
    g.fillText(this.hi.toFixed(0), 2, pad.t + 10);
    g.fillText(this.lo.toFixed(0), 2, h - pad.b);
    const states = this.report.states;
    this.report.joint_names.forEach((name, j) => {
      g.strokeStyle = PALETTE[j % PALETTE.length];
      g.beginPath();
      states.forEach((s, k) => (k ? g.lineTo(x(s.t_s), y(s.q_deg[j])) : g.moveTo(x(s.t_s), y(s.q_deg[j]))));
      g.stroke();
      g.fillStyle = g.strokeStyle;
      const unit = this.report.prismatic[j] ? ' (m)' : '';
      g.fillText(`${name}${unit}`, pad.l + (j % 4) * 60, h - 20 + Math.floor(j / 4) * 12);
    });
    g.strokeStyle = '#000';
    g.beginPath();
    g.moveTo(x(t), pad.t);
    g.lineTo(x(t), h - pad.b);
    g.stroke();
  }
}
