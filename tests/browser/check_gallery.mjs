// The gallery in real headless Chromium (issue #24), opened from file:// as a
// user would: no console errors, every image loaded, no horizontal overflow at
// 1280 px and 390 px (a phone), opening the page loads at most 5 MB (lazy
// pictures, <model-viewer> only on the first "Turn in 3D"), and every "Turn in
// 3D" view loads its mesh and paints pixels other than the background.
// Screenshots go to SHOTS.
//
// Usage: node check_gallery.mjs GALLERY_DIR SHOTS_DIR [CHROMIUM]
// Prints "ok   what" / "FAIL what" lines; exits 1 on any failure.
import { chromium } from "playwright-core";
import { mkdirSync, statSync } from "node:fs";
import { resolve } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const [gallery, shots, executable = "/usr/bin/chromium"] = process.argv.slice(2);
mkdirSync(shots, { recursive: true });
const url = pathToFileURL(resolve(gallery, "index.html")).href;
let failures = 0;
function check(what, ok, detail = "") {
  console.log(`${ok ? "ok  " : "FAIL"} ${what} ${detail}`);
  if (!ok) failures++;
}

const browser = await chromium.launch({
  executablePath: executable,
  // WebGL in software: the machine may have no GPU
  args: ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"],
});
const errors = [];
for (const [label, width, height] of [["desktop", 1280, 900], ["phone", 390, 844]]) {
  const page = await browser.newPage({ viewport: { width, height } });
  page.on("console", (m) => { if (m.type() === "error") errors.push(`${label}: ${m.text()}`); });
  page.on("pageerror", (e) => errors.push(`${label}: ${e.message}`));
  // what opening the page reads from disk, file by file (file:// has no
  // transfer sizes, so each file's size on disk)
  const opened = new Map();
  const onRequest = (r) => {
    if (!r.url().startsWith("file:")) return;
    try { opened.set(r.url(), statSync(fileURLToPath(r.url())).size); } catch { opened.set(r.url(), 0); }
  };
  page.on("request", onRequest);
  await page.goto(url, { waitUntil: "networkidle" });
  page.off("request", onRequest);
  const bytes = [...opened.values()].reduce((a, b) => a + b, 0);
  const biggest = [...opened.entries()].sort((a, b) => b[1] - a[1]).slice(0, 3)
    .map(([u, n]) => `${u.split("/").pop()} ${(n / 1e6).toFixed(2)} MB`);
  check(`${label}: opening the page loads at most 5 MB`, bytes <= 5e6,
    `${(bytes / 1e6).toFixed(2)} MB in ${opened.size} files; largest: ${biggest.join(", ")}`);
  // every image decoded (lazy ones scrolled to first)
  const images = await page.evaluate(async () => {
    const imgs = [...document.images];
    for (const img of imgs) { img.scrollIntoView(); if (!img.complete) await img.decode().catch(() => {}); }
    return imgs.map((i) => [i.getAttribute("src"), i.complete && i.naturalWidth > 0]);
  });
  const broken = images.filter(([, ok]) => !ok).map(([src]) => src);
  check(`${label}: every image loaded`, images.length > 0 && broken.length === 0,
    `${images.length - broken.length}/${images.length} ${broken.slice(0, 5).join(" ")}`);
  const overflow = await page.evaluate(() => {
    const wide = [...document.querySelectorAll("body *")].filter((e) => e.getBoundingClientRect().right > window.innerWidth + 0.5);
    return { scroll: document.documentElement.scrollWidth, inner: window.innerWidth,
      wide: wide.slice(0, 3).map((e) => e.tagName + (e.className ? "." + e.className : "") + ":" + (e.textContent || "").slice(0, 30)) };
  });
  check(`${label}: no horizontal overflow at ${width} px`, overflow.scroll <= overflow.inner && overflow.wide.length === 0,
    JSON.stringify(overflow));
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.screenshot({ path: `${shots}/gallery_${label}.png`, fullPage: false });
  if (label === "phone") { await page.close(); continue; }

  // every 3D view: press its button, wait for the mesh, count painted pixels
  const names = await page.$$eval(".view", (vs) => vs.map((v) => v.dataset.name));
  check("desktop: mesh cards have a 3D view", names.length > 0, `${names.length} views`);
  let painted = 0;
  for (const name of names) {
    const view = page.locator(`.view[data-name="${name}"]`);
    await view.scrollIntoViewIfNeeded();
    await view.locator("button.turn").click();
    let result;
    try {
      await page.waitForFunction((n) => document.querySelector(`.view[data-name="${n}"]`).classList.contains("loaded"),
        name, { timeout: 60000 });
      // model-viewer renders on the next frames; then read its canvas back
      result = await page.evaluate(async (n) => {
        const mv = document.querySelector(`.view[data-name="${n}"] model-viewer`);
        await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
        const blob = await mv.toBlob({ idealAspect: false });
        const bitmap = await createImageBitmap(blob);
        const c = new OffscreenCanvas(bitmap.width, bitmap.height);
        const g = c.getContext("2d");
        g.drawImage(bitmap, 0, 0);
        const d = g.getImageData(0, 0, c.width, c.height).data;
        // the background is transparent (the page's colour shows through)
        let n2 = 0;
        for (let i = 3; i < d.length; i += 4) if (d[i] > 0) n2++;
        return { painted: n2 / (d.length / 4), size: [c.width, c.height] };
      }, name);
    } catch (e) {
      result = { painted: 0, error: String(e).slice(0, 200) };
    }
    const ok = result.painted > 0.01;
    if (ok) painted++;
    check(`3D view ${name}: paints the mesh`, ok, JSON.stringify(result));
    if (ok && painted <= 3) await view.screenshot({ path: `${shots}/view_${name}.png` });
  }
  await page.locator(".view.loaded").first().scrollIntoViewIfNeeded();
  await page.screenshot({ path: `${shots}/gallery_desktop_3d.png`, fullPage: false });
  await page.close();
}
check("no console errors", errors.length === 0, errors.slice(0, 5).join(" | "));
await browser.close();
process.exit(failures ? 1 : 0);
