// asperity gallery: "Turn in 3D" on a card replaces its picture with a
// <model-viewer> of the card's mesh (drag to turn, wheel or pinch to zoom).
// The mesh comes from viewer/STEM.js, a script that calls asperityModel with the
// .glb bytes in base64: pages opened from file:// may load scripts but not fetch
// files. The copies are meshopt-compressed: <model-viewer> decodes them once
// its meshoptDecoderLocation, a classic script, has loaded. <model-viewer>
// itself (1 MB) is loaded on the first "Turn in 3D", so opening the page costs
// only the pictures. See crates/gallery/src/viewer.rs.
(function () {
  "use strict";
  var models = {}; // name -> blob: URL, or the callbacks waiting for it
  var base = document.currentScript.src.replace(/[^/]*$/, ""); // the viewer folder
  var viewerReady = null; // callbacks waiting for <model-viewer>, or null once loaded

  // Loads <model-viewer> once; calls done when it is defined, or failed if
  // its script cannot be loaded (every press waiting on it is told).
  function withViewer(done, failed) {
    if (window.customElements && customElements.get("model-viewer")) return done();
    if (viewerReady) return viewerReady.push([done, failed]);
    viewerReady = [[done, failed]];
    var script = document.createElement("script");
    script.src = base + "model-viewer-umd.min.js";
    function settle(ok) {
      var waiting = viewerReady;
      viewerReady = null;
      waiting.forEach(function (w) { w[ok ? 0 : 1](); });
    }
    script.onerror = function () { script.remove(); settle(false); };
    script.onload = function () {
      // the element's static setter loads the decoder script; the decoding is
      // done by the copy bundled in <model-viewer> once it has loaded
      customElements.get("model-viewer").meshoptDecoderLocation = base + "meshopt_decoder.js";
      settle(true);
    };
    document.head.appendChild(script);
  }

  window.asperityModel = function (name, base64) {
    var text = atob(base64);
    var bytes = new Uint8Array(text.length);
    for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
    var url = URL.createObjectURL(new Blob([bytes], { type: "model/gltf-binary" }));
    var waiting = models[name] || [];
    models[name] = url;
    waiting.forEach(function (done) { done(url); });
  };

  function model(name, src, done, failed) {
    if (typeof models[name] === "string") return done(models[name]);
    var first = !models[name];
    (models[name] = models[name] || []).push(done);
    if (!first) return;
    var script = document.createElement("script");
    script.src = src;
    script.onerror = failed;
    document.head.appendChild(script);
  }

  function turn(button) {
    var box = button.closest(".view");
    var picture = box.querySelector("img");
    button.disabled = true;
    button.textContent = "loading…";
    withViewer(function () { model(box.dataset.name, box.dataset.src, show, missing); }, missing);
    function missing() { button.textContent = "3D data missing"; }
    function show(url) {
      var viewer = document.createElement("model-viewer");
      viewer.setAttribute("src", url);
      viewer.setAttribute("alt", picture ? picture.alt : box.dataset.name);
      viewer.setAttribute("camera-controls", "");
      viewer.setAttribute("touch-action", "pan-y");
      viewer.setAttribute("shadow-intensity", "0.6");
      // asperity's meshes are white where they have no colours: tone them as the renders are
      viewer.setAttribute("exposure", "0.55");
      viewer.setAttribute("tone-mapping", "neutral");
      viewer.setAttribute("interaction-prompt", "none");
      viewer.addEventListener("load", function () {
        box.classList.add("loaded");
        button.remove();
      });
      viewer.addEventListener("error", function () {
        button.textContent = "3D view failed";
      });
      if (picture) box.replaceChild(viewer, picture); else box.appendChild(viewer);
    }
  }

  document.addEventListener("click", function (event) {
    var button = event.target.closest && event.target.closest("button.turn");
    if (button && !button.disabled) turn(button);
  });
})();
