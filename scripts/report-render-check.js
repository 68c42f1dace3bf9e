// Injected by scripts/check-report-render into a copy of a report page or figure: judges every
// top-level <svg> as Chromium laid it out and writes a JSON verdict into the DOM for --dump-dom.
// __SOURCES__ (the raw text of an HTML page's inline figures) and __MIN_MARKS__ are filled in.
(function () {
  var SOURCES = __SOURCES__, MIN_MARKS = __MIN_MARKS__;
  var SVG_NS = 'http://www.w3.org/2000/svg';
  // Axes, grid, tick labels, legend and colour bar are drawn in an empty plot too: not data.
  var NOT_DATA = '.grid, .ticks, .tick-labels, .legend, .colorbar';
  var SHAPES = 'path, line, polyline, polygon, circle, ellipse, rect, image, use';

  function coloured(paint) {  // a paint that shows on the white page
    if (!paint || paint === 'none') return false;
    var m = /^rgba?\((\d+), (\d+), (\d+)(?:, ([\d.]+))?\)$/.exec(paint);
    if (!m) return true;  // url(#gradient) and the like
    if (m[4] !== undefined && Number(m[4]) === 0) return false;
    return !(m[1] === '255' && m[2] === '255' && m[3] === '255');
  }

  function judge(svg) {
    var reasons = [], box = svg.getBoundingClientRect();
    var area = box.width * box.height, marks = 0;
    if (!(box.width > 0 && box.height > 0)) reasons.push('laid out with zero size');
    var shapes = svg.querySelectorAll(SHAPES);
    for (var i = 0; i < shapes.length; ++i) {
      var el = shapes[i], skip = el.closest(NOT_DATA);
      if ((skip && svg.contains(skip)) || el.classList.contains('frame')) continue;
      var st = getComputedStyle(el), r = el.getBoundingClientRect();
      if (st.display === 'none' || st.visibility === 'hidden' || Number(st.opacity) === 0) continue;
      if (el.localName === 'rect' && (st.fill === 'none' || r.width * r.height >= 0.9 * area))
        continue;  // an outline box (frame) or the background
      var painted = el.localName === 'image' || el.localName === 'use' ||
                    coloured(st.stroke) || (el.localName !== 'line' && coloured(st.fill));
      var extent = r.width > 0 || r.height > 0;
      var inside = r.right >= box.left && r.left <= box.right && r.bottom >= box.top &&
                   r.top <= box.bottom;
      if (painted && extent && inside) ++marks;
    }
    if (marks < MIN_MARKS)
      reasons.push('no data drawn: ' + marks + ' visible mark(s) besides background, frame, ' +
                   'axes and legend (need ' + MIN_MARKS + ')');
    var texts = svg.querySelectorAll('text'), words = 0, shown = 0;
    for (var k = 0; k < texts.length; ++k) {
      if (!texts[k].textContent.trim()) continue;
      ++words;
      if (texts[k].getComputedTextLength() > 0) ++shown;
    }
    if (words > 0 && shown === 0) reasons.push('no text renders (fonts missing?)');
    var fig = svg.closest('figure'), cap = fig && fig.querySelector('figcaption');
    return {caption: cap ? cap.textContent.trim() : '', marks: marks, reasons: reasons};
  }

  function check() {
    var verdict = {figures: [], page: []};
    try {
      var all = document.getElementsByTagNameNS(SVG_NS, 'svg'), svgs = [];
      for (var i = 0; i < all.length; ++i)
        if (!all[i].parentNode.closest || !all[i].parentNode.closest('svg')) svgs.push(all[i]);
      if (SOURCES !== null && SOURCES.length !== svgs.length)
        verdict.page.push(SOURCES.length + ' <svg> in the file but ' + svgs.length +
                          ' in the DOM (unclosed or misnested markup)');
      for (var j = 0; j < svgs.length; ++j) {
        var v = judge(svgs[j]);
        if (SOURCES !== null && j < SOURCES.length) {  // HTML forgives bad XML; a .svg will not
          var doc = new DOMParser().parseFromString(SOURCES[j], 'image/svg+xml');
          var err = doc.getElementsByTagName('parsererror')[0];
          if (err) {
            var msg = err.textContent.replace('This page contains the following errors:', '');
            v.reasons.push('not well-formed XML: ' + msg.split('Below is')[0].trim().slice(0, 200));
          }
        }
        verdict.figures.push(v);
      }
    } catch (e) {
      verdict.page.push('check script failed: ' + e);
    }
    var root = document.body || document.documentElement;
    var out = document.createElementNS(root.namespaceURI, root === document.body ? 'pre' : 'desc');
    out.setAttribute('id', 'loopscan-render-verdict');
    out.textContent = JSON.stringify(verdict);
    root.appendChild(out);
  }

  window.addEventListener('load', check);
})();
