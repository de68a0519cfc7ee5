#!/usr/bin/env node
// Screenshots of a plan page (hfts-client view) at given times of its
// animation, in headless Chromium (Debian's /usr/bin/chromium, driven by
// puppeteer-core): the pictures of docs/placement.md.
//   node viewer/tools/snapshot_viewer.js PAGE.html OUT_PREFIX T1,T2,... [--chromium PATH]
// writes OUT_PREFIX_1.png, OUT_PREFIX_2.png, ... (one per time, in s; a
// time beyond the animation shows its end).
'use strict';
const path = require('path');
const puppeteer = require('puppeteer-core');

async function main() {
  const [pageFile, prefix, timeList] = process.argv.slice(2);
  const at = process.argv.indexOf('--chromium');
  const chromium = at > 0 ? process.argv[at + 1] : '/usr/bin/chromium';
  const times = (timeList || '').split(',').map(Number);
  if (!pageFile || !prefix || times.length === 0 || times.some((t) => !Number.isFinite(t))) {
    console.error('usage: snapshot_viewer.js PAGE.html OUT_PREFIX T1,T2,... [--chromium PATH]');
    process.exit(2);
  }
  const browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
           '--allow-file-access-from-files', '--window-size=1000,700'],
  });
  try {
    const page = await browser.newPage();
    await page.setViewport({width: 1000, height: 700});
    await page.goto('file://' + path.resolve(pageFile));
    await page.waitForFunction('window.viewerReady === true', {timeout: 90000});
    for (let i = 0; i < times.length; ++i) {
      await page.evaluate((t) => window.viewer.setTime(Math.min(t, window.viewer.duration)),
                          times[i]);
      await page.screenshot({path: `${prefix}_${i + 1}.png`});
    }
  } finally {
    await browser.close();
  }
}

main().catch((e) => {
  console.error(String(e));
  process.exit(1);
});
