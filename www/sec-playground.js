// <sec-playground> in one classic script, for any course page:
//
//   <script src="sec-playground/www/sec-playground.js"></script>
//   <sec-playground task="double-t-maze" autoplay></sec-playground>
//
// Served over HTTP it loads the element (element.js, an ES module). Opened from disk (file://),
// where browsers load no modules, it says so inside every <sec-playground> that has no text of
// its own, instead of leaving the element blank. (A classic script, so it runs from disk too.)
(function () {
  var script = document.currentScript;
  if (location.protocol !== 'file:') {
    import(new URL('element.js', script.src).href);
    return;
  }
  var style = document.createElement('style');
  style.textContent = 'sec-playground { display: block; }'
    + ' sec-playground p.sec-playground-file { font: 15px/1.5 system-ui, sans-serif; padding: 12px;'
    + ' border: 1px dashed #999; }';
  document.head.append(style);
  var say = function (el) {
    if (el.textContent.trim()) return; // the page's own fallback
    var p = document.createElement('p');
    p.className = 'sec-playground-file';
    p.textContent = 'The SEC playground has to be served over HTTP: browsers do not load its modules from a page '
      + 'opened from disk. In this page\'s folder run "python3 -m http.server 8000" and open '
      + 'http://localhost:8000/ instead.';
    el.append(p);
  };
  var all = function () { document.querySelectorAll('sec-playground').forEach(say); };
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', all);
  else all();
})();
