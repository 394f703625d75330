// "See it in your room" (swatch.catalog.ar, on the page when the spec's [presets] ar is on): a card's button
// loads the vendored <model-viewer> (an ES module next to the page, named by its data-viewer) on first use and opens
// the swatch's viewer file in the card: a 3-D view the pointer turns, with <model-viewer>'s AR button where the
// device offers AR (WebXR on Android phones; Quick Look with the swatch's USDZ on iPhone and iPad). Tone mapping
// is off, as the colour errors beside the button were measured.
function setupAR() {
  let loading = null;
  function load(script) {
    if (loading === null) {
      loading = new Promise((resolve, reject) => {
        const tag = document.createElement("script");
        tag.type = "module";
        tag.src = script;
        tag.onload = resolve;
        tag.onerror = () => reject(new Error("could not load " + script));
        document.head.appendChild(tag);
      }).then(() => customElements.whenDefined("model-viewer"));
    }
    return loading;
  }
  function open(button) {
    const box = button.parentElement;
    const shown = box.querySelector("model-viewer, .ar-error");
    if (shown) {  // a second press closes it
      shown.remove();
      button.setAttribute("aria-expanded", "false");
      return;
    }
    const viewer = document.createElement("model-viewer");
    const attrs = { src: button.dataset.src, ar: "", "ar-modes": "webxr quick-look", "camera-controls": "",
                    "tone-mapping": "none", "shadow-intensity": "1", "interaction-prompt": "none",
                    alt: button.getAttribute("aria-label") };
    if (button.dataset.iosSrc) attrs["ios-src"] = button.dataset.iosSrc;
    for (const [k, v] of Object.entries(attrs)) viewer.setAttribute(k, v);
    const arButton = document.createElement("button");
    arButton.type = "button";
    arButton.slot = "ar-button";
    arButton.className = "ar-place";
    arButton.textContent = "place it in your room (AR)";
    viewer.appendChild(arButton);
    box.appendChild(viewer);
    button.setAttribute("aria-expanded", "true");
    load(button.dataset.viewer).catch(() => {
      const note = document.createElement("p");
      note.className = "ar-error";
      note.textContent = "The 3-D view needs the catalog served over http(s): a page opened from a file cannot load it.";
      viewer.replaceWith(note);
    });
  }
  document.addEventListener("click", (event) => {
    const button = event.target instanceof Element ? event.target.closest("button.ar-open") : null;
    if (button) open(button);
  });
}
setupAR();
