// Evaluated in every built page by test_site_render.py once the page has loaded: waits for MathJax to
// typeset, then reports what a reader would see wrong. Returns plain data (JSON).
(async () => {
  const sleep = ms => new Promise(r => setTimeout(r, ms));
  if (document.querySelector('.math')) {
    for (let i = 0; i < 400 && !(window.MathJax && MathJax.Hub && MathJax.isReady); i++) await sleep(25);
    if (window.MathJax && MathJax.Hub) await new Promise(r => MathJax.Hub.Queue(r));
  }
  const art = document.querySelector('article') || document.body;
  const visible = el => {  // the text a reader sees: no code, scripts, typeset math or heading links
    const c = el.cloneNode(true);
    c.querySelectorAll('pre, code, script, style, .MathJax_CHTML, .MJX_Assistive_MathML, .MathJax_Preview, ' +
                       '.headerlink, .math').forEach(e => e.remove());
    return c.textContent.replace(/\s+/g, ' ');
  };
  const tex = /\\\(|\\\)|\\\[|\\\]|\$\$|\$[^$\s][^$]{0,80}\$|\\(frac|sqrt|mathbf|delta|gamma|left|right|cdot|sum|ln|pi|beta|mu|omega)\b/g;
  const text = visible(art);
  const raw = [...text.matchAll(tex)].map(m => text.slice(Math.max(0, m.index - 30), m.index + 40));
  const untypeset = [...art.querySelectorAll('.math')].filter(e => !e.querySelector('.MathJax_CHTML'))
    .map(e => e.textContent.slice(0, 60));
  // a formula written as text in a table cell: sqrt(..), powers, starred effective quantities, fractions of symbols
  const formula = /sqrt\(|\)\^|\^\(|\^[0-9]|√|[A-Za-zδγμ]\* ?[=/·)]|\(1\/[0-9]\)|\b[a-zA-Zγδμ]_\{/;
  const plainFormulas = [];
  art.querySelectorAll('td, th').forEach(td => {
    const t = visible(td);
    if (formula.test(t)) plainFormulas.push(t.trim().slice(0, 80));
  });
  // the same in running text: paragraphs and list items outside tables (the innermost block, once)
  const plainProse = [];
  art.querySelectorAll('p, li, dd').forEach(e => {
    if (e.closest('table') || e.querySelector('p, li, dd')) return;
    // (a power of ten written as a count, "10^7 executions", is a number, not a formula)
    const t = visible(e).replace(/\b10\^[0-9]+\b/g, ''), m = t.match(formula);
    if (m) plainProse.push(t.slice(Math.max(0, m.index - 40), m.index + 40).trim());
  });
  const headings = [...art.querySelectorAll('h2')].map(h => visible(h).trim());
  const ids = [...document.querySelectorAll('[id]')].map(e => e.id);
  const links = [...art.querySelectorAll('a[href]')].map(a => a.getAttribute('href'));
  return {raw, untypeset, plainFormulas, plainProse, headings, ids, links};
})()
