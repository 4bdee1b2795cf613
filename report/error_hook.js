(function () {
  var pending = [];
  function show(message) {
    var list = document.getElementById('report-errors');
    if (!list) { pending.push(message); return; }
    var item = document.createElement('li');
    item.className = 'report-error';
    item.textContent = message;
    list.appendChild(item);
  }
  window.addEventListener('error', function (e) {
    var where = e.filename ? ' (' + e.filename.slice(-60) + ':' + e.lineno + ')' : '';
    var what = e.message || (e.target && e.target.tagName ? e.target.tagName + ' failed to load' : e.type);
    show('error: ' + what + where);
  }, true);
  window.addEventListener('unhandledrejection', function (e) { show('unhandled rejection: ' + e.reason); });
  var original = console.error;
  console.error = function () {
    show('console.error: ' + Array.prototype.join.call(arguments, ' '));
    return original.apply(console, arguments);
  };
  document.addEventListener('DOMContentLoaded', function () { pending.splice(0).forEach(show); });
})();
