// asperity gallery: "Turn in 3D" on a card replaces its picture with a
// <model-viewer> of the card's mesh (drag to turn, wheel or pinch to zoom).
// The mesh comes from viewer/STEM.js, a script that calls asperityModel with the
// .glb bytes in base64: pages opened from file:// may load scripts but not fetch
// files. See crates/gallery/src/viewer.rs.
(function () {
  "use strict";
  var models = {}; // name -> blob: URL, or the callbacks waiting for it

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
    model(box.dataset.name, box.dataset.src, function (url) {
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
    }, function () {
      button.textContent = "3D data missing";
    });
  }

  document.addEventListener("click", function (event) {
    var button = event.target.closest && event.target.closest("button.turn");
    if (button && !button.disabled) turn(button);
  });
})();
