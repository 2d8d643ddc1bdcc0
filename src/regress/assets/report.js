(function () {
  "use strict";
  function select(name) {
    var card = document.getElementById(name);
    if (!card || !card.classList.contains("case")) return;
    card.open = true;
    document.querySelectorAll(".selected").forEach(function (e) {
      e.classList.remove("selected");
    });
    card.classList.add("selected");
    var row = document.querySelector('#summary tr[data-case="' + CSS.escape(name) + '"]');
    if (row) row.classList.add("selected");
    card.scrollIntoView({block: "start"});
  }
  function fromHash() { select(decodeURIComponent(location.hash.slice(1))); }
  window.addEventListener("hashchange", fromHash);
  document.querySelectorAll("#summary tbody tr").forEach(function (tr) {
    tr.addEventListener("click", function (e) {
      e.preventDefault();
      if (location.hash === "#" + tr.dataset.case) select(tr.dataset.case);
      else location.hash = tr.dataset.case;
    });
  });
  var failedOnly = document.getElementById("failed-only");
  if (failedOnly) failedOnly.addEventListener("change", function () {
    document.body.classList.toggle("failed-only", failedOnly.checked);
  });
  // Sorting: a click on a column header sorts by it (numbers by value), a second reverses.
  var summary = document.getElementById("summary");
  if (summary) summary.querySelectorAll("th").forEach(function (th, col) {
    th.addEventListener("click", function () {
      var up = !th.classList.contains("sorted-up");
      summary.querySelectorAll("th").forEach(function (h) {
        h.classList.remove("sorted-up", "sorted-down");
      });
      th.classList.add(up ? "sorted-up" : "sorted-down");
      var body = summary.tBodies[0], rows = Array.prototype.slice.call(body.rows);
      function key(r) {
        var c = r.cells[col], v = c.dataset.v;
        return v === undefined ? c.textContent : (v === "" ? NaN : parseFloat(v));
      }
      rows.sort(function (a, b) {
        var x = key(a), y = key(b), d;
        if (typeof x === "number") d = (isNaN(x) ? Infinity : x) - (isNaN(y) ? Infinity : y);
        else d = x < y ? -1 : x > y ? 1 : 0;
        return up ? d : -d;
      });
      rows.forEach(function (r) { body.appendChild(r); });
    });
  });
  // Each case's images: flip render / reference, magnify under the mouse.
  var hovered = null;
  document.querySelectorAll(".viewer").forEach(function (v) {
    var flip = v.querySelector("img.flip"), shown = v.querySelector(".shown");
    var loupes = v.querySelectorAll(".loupe"), where = v.querySelector(".where");
    var w = +v.dataset.w, h = +v.dataset.h, zoom = 8, timer = null;
    var at = {x: Math.floor(w / 2), y: Math.floor(h / 2)}; // until the mouse moves
    function show(which) {
      if (!flip || !flip.dataset[which]) return;
      flip.src = flip.dataset[which];
      flip.alt = which;
      v.dataset.shown = which;
      if (shown) shown.textContent = which;
    }
    v.flip = function () { show(v.dataset.shown === "render" ? "reference" : "render"); };
    if (flip && flip.dataset.reference) {
      flip.addEventListener("click", v.flip);
      v.querySelector("button.flip").addEventListener("click", v.flip);
      v.querySelector("input.blink").addEventListener("change", function (e) {
        clearInterval(timer);
        if (e.target.checked) timer = setInterval(v.flip, 600);
      });
    }
    function update() {
      if (!at) return;
      var half = loupes.length ? loupes[0].clientWidth / 2 : 0;
      loupes.forEach(function (l) {
        l.style.backgroundImage = 'url("' + l.dataset.src + '")';
        l.style.backgroundSize = w * zoom + "px " + h * zoom + "px";
        l.style.backgroundPosition = (half - (at.x + 0.5) * zoom) + "px " +
                                     (half - (at.y + 0.5) * zoom) + "px";
        l.style.setProperty("--z", zoom + "px");
      });
      where.textContent = "pixel (" + at.x + ", " + at.y + "), magnified " + zoom +
                          "\u00d7 (wheel over an image zooms)";
    }
    function look(img, e) {
      var r = img.getBoundingClientRect();
      at = {x: Math.min(w - 1, Math.max(0, Math.floor((e.clientX - r.left) / r.width * w))),
            y: Math.min(h - 1, Math.max(0, Math.floor((e.clientY - r.top) / r.height * h)))};
      update();
    }
    v.querySelectorAll("img").forEach(function (img) {
      img.addEventListener("mousemove", function (e) { look(img, e); });
      img.addEventListener("mouseenter", function () { hovered = v; });
      img.addEventListener("wheel", function (e) {
        e.preventDefault();
        zoom = Math.max(2, Math.min(64, e.deltaY < 0 ? zoom * 2 : zoom / 2));
        look(img, e);
      }, {passive: false});
    });
    update();
  });
  document.addEventListener("keydown", function (e) {
    if (e.key !== "f" && e.key !== "F") return;
    var v = hovered || document.querySelector("details.selected .viewer");
    if (v && v.flip) v.flip();
  });
  fromHash();
})();
