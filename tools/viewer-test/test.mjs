// Opens a page written by `foldsim view` in headless Chromium and checks it: no console
// errors, the structure drawn (the canvas is not blank), moving the time slider changes the
// picture, and each plotted column has an axis of its own with ticks. Then opens it again
// with WebGL switched off: the page must say so in words and still draw the plot. Saves
// screenshots at the first and last time, and of the page without WebGL. The address's
// `#t=T` must open the page at T.
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
const axes = await page.evaluate(() => window.foldsimView.plotAxes || []);
const columns = await page.evaluate(() => window.FOLDSIM_DATA.plot.names);
const first = await slide(0);
await page.screenshot({ path: path.join(shots, path.basename(pagePath, '.html') + '-start.png') });
const last = await slide(Number(at));
await page.screenshot({ path: path.join(shots, path.basename(pagePath, '.html') + '-end.png') });
// The address sets the time shown: `#t=T` opens the page paused at T.
const duration = await page.evaluate(() => window.foldsimView.duration);
const wanted = Math.round(0.5 * duration * 1000) / 1000;
const page3 = await browser.newPage({ viewport: { width: 1280, height: 720 } });
page3.on('pageerror', (e) => errors.push(String(e)));
await page3.goto('file://' + path.resolve(pagePath) + '#t=' + wanted);
await page3.waitForFunction(() => window.foldsimView && window.foldsimView.ready, null, { timeout: 120000 });
await page3.waitForTimeout(300);
const shown = await page3.evaluate(() => window.foldsimView.now());
await browser.close();

// Without WebGL: a message where the structure would be, the plot still drawn.
const bare = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--disable-3d-apis', '--disable-webgl', '--no-sandbox'],
});
const page2 = await bare.newPage({ viewport: { width: 1280, height: 720 } });
const errors2 = [];
page2.on('pageerror', (e) => errors2.push(String(e)));
await page2.goto('file://' + path.resolve(pagePath));
await page2.waitForFunction(() => window.foldsimView && window.foldsimView.ready, null, { timeout: 60000 });
const without = await page2.evaluate(() => ({
  note: (document.getElementById('nowebgl') || {}).textContent || '',
  axes: (window.foldsimView.plotAxes || []).length,
}));
await page2.screenshot({ path: path.join(shots, path.basename(pagePath, '.html') + '-nowebgl.png') });
await bare.close();

// The background is a light grey (luminance ~245): pixels far from it are the structure.
const drawn = first.filter((v) => Math.abs(v - 245) > 12).length / first.length;
const changed = first.filter((v, i) => Math.abs(v - last[i]) > 12).length / first.length;
const problems = [];
if (errors.length) problems.push('console errors: ' + errors.join(' | '));
if (drawn < 0.01) problems.push(`the canvas is blank (${(100 * drawn).toFixed(2)} % drawn)`);
if (changed < 0.005) problems.push(`moving the slider changed ${(100 * changed).toFixed(2)} % of the picture`);
if (Math.abs(shown - wanted) > 1e-9) problems.push(`#t=${wanted} opened the page at t = ${shown}`);
if (axes.length !== columns.length) problems.push(`${columns.length} plotted columns but ${axes.length} axes`);
for (const a of axes) if (a.ticks.length < 2) problems.push(`the axis of ${a.name} has ${a.ticks.length} ticks`);
if (!without.note.includes('no WebGL')) problems.push('without WebGL the page does not say so');
if (without.axes !== columns.length) problems.push(`without WebGL the plot has ${without.axes} axes`);
if (errors2.length) problems.push('errors without WebGL: ' + errors2.join(' | '));
console.log(`${pagePath}: #t=${wanted} shown at ${shown}; ${(100 * drawn).toFixed(1)} % of the canvas drawn, ${(100 * changed).toFixed(1)} % changed by the slider, ${errors.length} console errors, ${axes.length} plot axes; without WebGL: ${without.note ? 'said so' : 'silent'}, ${without.axes} axes`);
if (problems.length) {
  console.error(problems.join('\n'));
  process.exit(1);
}
