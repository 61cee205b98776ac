// Opens a page written by `foldsim view` in headless Chromium and checks it: no console
// errors, the structure drawn (the canvas is not blank), and moving the time slider changes
// the picture. Saves screenshots at the first and last time.
// Usage: node tools/viewer-test/test.mjs PAGE.html SHOTS_DIR [FRACTION_OF_DURATION]
import { chromium } from 'playwright-core';
import path from 'path';

const [pagePath, shots, at = '1'] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-sandbox'],
});
const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
const errors = [];
page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
page.on('pageerror', (e) => errors.push(String(e)));
await page.goto('file://' + path.resolve(pagePath));
await page.waitForFunction(() => window.foldsimView && (window.foldsimView.ready || window.foldsimView.error), null, { timeout: 120000 });
const slide = async (fraction) => page.evaluate((f) => {
  const s = document.getElementById('slider');
  s.value = String(f * window.foldsimView.duration);
  s.dispatchEvent(new Event('input'));
  return window.foldsimView.pixels();
}, fraction);
const first = await slide(0);
await page.screenshot({ path: path.join(shots, path.basename(pagePath, '.html') + '-start.png') });
const last = await slide(Number(at));
await page.screenshot({ path: path.join(shots, path.basename(pagePath, '.html') + '-end.png') });
await browser.close();

// The background is a light grey (luminance ~245): pixels far from it are the structure.
const drawn = first.filter((v) => Math.abs(v - 245) > 12).length / first.length;
const changed = first.filter((v, i) => Math.abs(v - last[i]) > 12).length / first.length;
const problems = [];
if (errors.length) problems.push('console errors: ' + errors.join(' | '));
if (drawn < 0.01) problems.push(`the canvas is blank (${(100 * drawn).toFixed(2)} % drawn)`);
if (changed < 0.005) problems.push(`moving the slider changed ${(100 * changed).toFixed(2)} % of the picture`);
console.log(`${pagePath}: ${(100 * drawn).toFixed(1)} % of the canvas drawn, ${(100 * changed).toFixed(1)} % changed by the slider, ${errors.length} console errors`);
if (problems.length) {
  console.error(problems.join('\n'));
  process.exit(1);
}
