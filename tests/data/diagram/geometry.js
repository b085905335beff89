// Geometry checks of the diagrams embedded in the page, run by headless
// Chromium (browser_test.sh): every node lies inside its parent state's box
// (or inside the drawing for top-level nodes), no two texts overlap, every
// expected state is drawn, and the drawing's aspect ratio is within
// `data-max-aspect` when given. Bounding boxes come from the DOM.
(function () {
  const out = [];
  const eps = 0.5;
  const inside = (a, b) =>
    a.left >= b.left - eps && a.top >= b.top - eps && a.right <= b.right + eps && a.bottom <= b.bottom + eps;
  const overlap = (a, b) =>
    a.left < b.right - eps && b.left < a.right - eps && a.top < b.bottom - eps && b.top < a.bottom - eps;
  const box = (g) => (g.querySelector(':scope > rect.node-box') || g.querySelector(':scope > circle') || g).getBoundingClientRect();
  for (const svg of document.querySelectorAll('svg.robosim-diagram')) {
    const name = svg.getAttribute('data-name');
    const drawing = svg.querySelector('rect.background').getBoundingClientRect();
    const problems = [];
    const nodes = Array.from(svg.querySelectorAll('g.node, g.block'));
    for (const g of nodes) {
      const id = g.getAttribute('data-id');
      const parentId = g.getAttribute('data-parent');
      let parentBox = drawing;
      let parentName = 'the drawing';
      if (parentId) {
        const p = nodes.find((n) => n.getAttribute('data-id') === parentId);
        if (!p) { problems.push(`${id}: parent ${parentId} is not drawn`); continue; }
        // Below the parent's header.
        const r = p.querySelector(':scope > rect.node-box').getBoundingClientRect();
        const sep = p.querySelector(':scope > line.separator');
        const top = sep ? sep.getBoundingClientRect().top : r.top;
        parentBox = { left: r.left, right: r.right, top, bottom: r.bottom };
        parentName = parentId;
        if (!(p.contains(g))) problems.push(`${id}: not nested in the group of ${parentId}`);
      }
      if (!inside(box(g), parentBox)) problems.push(`${id} is not inside ${parentName}`);
    }
    const texts = Array.from(svg.querySelectorAll('text.label')).map((t) => [t.textContent, t.getBoundingClientRect()]);
    for (let i = 0; i < texts.length; i++) {
      for (let j = i + 1; j < texts.length; j++) {
        if (overlap(texts[i][1], texts[j][1])) problems.push(`labels overlap: "${texts[i][0]}" and "${texts[j][0]}"`);
      }
      if (!inside(texts[i][1], drawing)) problems.push(`label "${texts[i][0]}" is outside the drawing`);
    }
    // Neither wider than `max` times its height nor taller than `max` times its width.
    const max = Number(svg.parentElement.getAttribute('data-max-aspect') || '0');
    if (max > 0) {
      const ratio = drawing.width / drawing.height;
      if (ratio > max || ratio < 1 / max) problems.push(`the drawing is ${Math.round(drawing.width)} × ${Math.round(drawing.height)}, beyond ${max}:1`);
    }
    const expected = (svg.parentElement.getAttribute('data-expect-states') || '').split(' ').filter((s) => s);
    for (const s of expected) {
      if (!nodes.some((n) => n.getAttribute('data-id') === s && n.getAttribute('data-kind') === 'state')) problems.push(`state ${s} is not drawn`);
    }
    out.push(`${problems.length ? 'FAIL' : 'PASS'} ${name} (${nodes.length} nodes, ${texts.length} texts)` + problems.map((p) => `\n  ${p}`).join(''));
  }
  const pre = document.createElement('pre');
  pre.id = 'result';
  pre.textContent = out.join('\n');
  document.body.appendChild(pre);
})();
