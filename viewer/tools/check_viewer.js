#!/usr/bin/env node
// Opens a plan page (hfts-client view) in headless Chromium (Debian's
// /usr/bin/chromium, driven by puppeteer-core) and reports, as JSON: the
// console errors, what the viewer drew (contacts, markers, animated
// nodes), how many pixels change between the first and the last frame
// near the palm's two screen positions, and the red (contact) pixels of
// the first frame (the fingers cover the contacts in the last), the sensed
// points drawn (and the violet pixels of the first frame). With a
// simulated lift (the glTF's "simulated" animation), also how far the
// object's node moves from its start to the end of the lift (m) and the
// phase shown there. Writes first.png and last.png (and lifted.png) to OUTDIR.
//   node viewer/tools/check_viewer.js PAGE.html OUTDIR [--chromium PATH]
'use strict';
const fs = require('fs');
const path = require('path');
const puppeteer = require('puppeteer-core');

async function main() {
  const [page_, outDir] = process.argv.slice(2);
  const at = process.argv.indexOf('--chromium');
  const chromium = at > 0 ? process.argv[at + 1] : '/usr/bin/chromium';
  if (!page_ || !outDir) {
    console.error('usage: check_viewer.js PAGE.html OUTDIR [--chromium PATH]');
    process.exit(2);
  }
  fs.mkdirSync(outDir, {recursive: true});
  const browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--allow-file-access-from-files', '--window-size=1200,800'],
  });
  const errors = [];
  try {
    const page = await browser.newPage();
    await page.setViewport({width: 1200, height: 800});
    page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
    page.on('pageerror', (e) => errors.push(String(e)));
    await page.goto('file://' + path.resolve(page_));
    const plan = await page.evaluate(() => window.HFTS_PLAN);
    await page.waitForFunction('window.viewerReady === true', {timeout: 90000});
    const grab = async (time, file) => {
      const palm = await page.evaluate((t) => {
        window.viewer.setTime(t);
        return window.viewer.screenPosition('palm');
      }, time);
      await page.screenshot({path: path.join(outDir, file)});
      return palm;
    };
    const viewer = await page.evaluate(() => ({
      duration: window.viewer.duration, contacts: window.viewer.contacts,
      markers: window.viewer.markers, explored: window.viewer.explored,
      points: window.viewer.points, animatedNodes: window.viewer.animatedNodes}));
    // Pixels of the canvas at both ends, compared in the page.
    const comparison = await page.evaluate(() => {
      const canvas = document.querySelector('#view canvas');
      const copy = document.createElement('canvas');
      copy.width = canvas.width;
      copy.height = canvas.height;
      const context = copy.getContext('2d');
      const pixels = (t) => {
        window.viewer.setTime(t);
        context.drawImage(canvas, 0, 0);
        return context.getImageData(0, 0, copy.width, copy.height).data;
      };
      const ratio = canvas.width / canvas.getBoundingClientRect().width;
      window.viewer.setTime(0);
      const start = window.viewer.screenPosition('palm');
      const first = pixels(0);
      window.viewer.setTime(window.viewer.duration);
      const end = window.viewer.screenPosition('palm');
      const last = pixels(window.viewer.duration);
      let changed = 0, nearPalm = 0, red = 0, violet = 0;
      const near = (x, y, p) => Math.abs(x - p.x * ratio) < 60 * ratio && Math.abs(y - p.y * ratio) < 60 * ratio;
      for (let i = 0; i < first.length; i += 4) {
        const d = Math.abs(first[i] - last[i]) + Math.abs(first[i + 1] - last[i + 1]) +
                  Math.abs(first[i + 2] - last[i + 2]);
        const x = (i / 4) % copy.width, y = Math.floor(i / 4 / copy.width);
        if (d > 60) {
          ++changed;
          if (near(x, y, start) || near(x, y, end)) ++nearPalm;
        }
        if (first[i] > 170 && first[i + 1] < 90 && first[i + 2] < 90) ++red;
        if (first[i] > 120 && first[i + 2] > 160 && first[i + 1] < 0.6 * first[i + 2]) ++violet;
      }
      return {pixels: first.length / 4, changed, changedNearPalm: nearPalm, redPixels: red,
              violetPixels: violet,
              palmStart: start, palmEnd: end};
    });
    await grab(0, 'first.png');
    await grab(viewer.duration, 'last.png');
    const simulated = await page.evaluate((object) => {
      const v = window.viewer;
      if (!v.clips.includes('simulated') || !v.selectClip('simulated')) return {clips: v.clips};
      // The trial's phases: settle 0.3 s, close 1 s, lift 1 s (docs/physics.md).
      v.setTime(0);
      const start = v.worldPosition(object);
      v.setTime(2.3);
      const lifted = v.worldPosition(object);
      const moved = Math.hypot(lifted.x - start.x, lifted.y - start.y, lifted.z - start.z);
      return {clips: v.clips, simulatedDuration: v.duration, objectMoved: moved,
              phaseAtLift: v.phase()};
    }, plan.object);
    if (simulated.objectMoved !== undefined) await page.screenshot({path: path.join(outDir, 'lifted.png')});
    console.log(JSON.stringify({consoleErrors: errors, ...viewer, ...comparison, ...simulated}));
  } finally {
    await browser.close();
  }
}

main().catch((e) => {
  console.error('check_viewer: ' + (e.stack || e));
  process.exit(1);
});
