// The scene's expressions in the browser: the part of muParser's language a scene uses
// (numbers, parameter names, + - * / ^, unary minus, comparisons, && ||, ?:, its built-in
// functions and the constants _pi, _e), with muParser's precedences (^ binds tighter than a
// unary minus: -2^2 = -4). compileExpression(text, names) returns f(values) over the values
// in the order of `names`; preview.js checks each against vkrecon's value when the page loads.
var compileExpression = (function () {
  'use strict';
  var functions = {
    sin: Math.sin, cos: Math.cos, tan: Math.tan, asin: Math.asin, acos: Math.acos, atan: Math.atan,
    sinh: Math.sinh, cosh: Math.cosh, tanh: Math.tanh, asinh: Math.asinh, acosh: Math.acosh, atanh: Math.atanh,
    log2: Math.log2, log10: Math.log10, log: Math.log, ln: Math.log, exp: Math.exp, sqrt: Math.sqrt,
    sign: Math.sign, abs: Math.abs,
    rint: function (x) { var r = Math.round(x); return Math.abs(x % 1) === 0.5 && r % 2 ? r - 1 : r; },  // half to even
    min: Math.min, max: Math.max,
    sum: function () { var s = 0; for (var i = 0; i < arguments.length; ++i) s += arguments[i]; return s; },
    avg: function () { var s = 0; for (var i = 0; i < arguments.length; ++i) s += arguments[i]; return s / arguments.length; }
  };
  var constants = {_pi: Math.PI, _e: Math.E};
  // Binary operators by precedence (muParser's prLOGIC_OR … prPOW); ^ alone is right-associative.
  var binary = {
    '||': [1, function (a, b) { return a || b ? 1 : 0; }], '&&': [2, function (a, b) { return a && b ? 1 : 0; }],
    '<': [4, function (a, b) { return a < b ? 1 : 0; }], '>': [4, function (a, b) { return a > b ? 1 : 0; }],
    '<=': [4, function (a, b) { return a <= b ? 1 : 0; }], '>=': [4, function (a, b) { return a >= b ? 1 : 0; }],
    '==': [4, function (a, b) { return a === b ? 1 : 0; }], '!=': [4, function (a, b) { return a !== b ? 1 : 0; }],
    '+': [5, function (a, b) { return a + b; }], '-': [5, function (a, b) { return a - b; }],
    '*': [6, function (a, b) { return a * b; }], '/': [6, function (a, b) { return a / b; }],
    '^': [7, function (a, b) { return Math.pow(a, b); }]
  };
  var kUnary = 6;  // muParser's prINFIX: a unary minus binds like * and /

  function tokenize(text) {
    var tokens = [], re = /\s*(?:(\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?)|([A-Za-z_][A-Za-z0-9_]*)|(\|\||&&|<=|>=|==|!=|[-+*/^<>(),?:]))/y;
    var at = 0;
    while (at < text.length) {
      if (/^\s*$/.test(text.slice(at))) break;
      re.lastIndex = at;
      var m = re.exec(text);
      if (!m) throw new Error('cannot read "' + text.slice(at) + '" in ' + text);
      tokens.push(m[1] !== undefined ? {number: parseFloat(m[1])} : m[2] !== undefined ? {name: m[2]} : {op: m[3]});
      at = re.lastIndex;
    }
    return tokens;
  }

  return function (text, names) {
    var tokens = tokenize(text), at = 0;
    function peek(op) { return at < tokens.length && tokens[at].op === op; }
    function expect(op) {
      if (!peek(op)) throw new Error('expected "' + op + '" in ' + text);
      ++at;
    }
    function primary() {
      var t = tokens[at++];
      if (!t) throw new Error('unexpected end of ' + text);
      if (t.number !== undefined) return function () { return t.number; };
      if (t.op === '(') { var inner = ternary(); expect(')'); return inner; }
      if (t.op === '-' || t.op === '+') {
        var operand = binaryAbove(kUnary);
        return t.op === '-' ? function (v) { return -operand(v); } : operand;
      }
      if (t.name !== undefined) {
        if (peek('(')) {
          var f = functions[t.name];
          if (!f) throw new Error('unknown function ' + t.name + ' in ' + text);
          ++at;
          var args = [ternary()];
          while (peek(',')) { ++at; args.push(ternary()); }
          expect(')');
          return function (v) { return f.apply(null, args.map(function (a) { return a(v); })); };
        }
        if (t.name in constants) return function () { return constants[t.name]; };
        var index = names.indexOf(t.name);
        if (index < 0) throw new Error('unknown name ' + t.name + ' in ' + text);
        return function (v) { return v[index]; };
      }
      throw new Error('unexpected "' + t.op + '" in ' + text);
    }
    // Operators that bind tighter than `level`, by precedence climbing.
    function binaryAbove(level) {
      var left = primary();
      for (;;) {
        var t = tokens[at], entry = t && t.op && binary[t.op];
        if (!entry || entry[0] <= level) return left;
        ++at;
        var right = binaryAbove(t.op === '^' ? entry[0] - 1 : entry[0]), apply = entry[1], l = left;
        left = (function (l, r, f) { return function (v) { return f(l(v), r(v)); }; })(l, right, apply);
      }
    }
    function ternary() {
      var condition = binaryAbove(0);
      if (!peek('?')) return condition;
      ++at;
      var yes = ternary();
      expect(':');
      var no = ternary();
      return function (v) { return condition(v) ? yes(v) : no(v); };
    }
    var f = ternary();
    if (at !== tokens.length) throw new Error('unexpected "' + (tokens[at].op || tokens[at].name) + '" in ' + text);
    return f;
  };
})();
