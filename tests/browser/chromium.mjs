// How the browser tests, the viewer benchmarks and the README's picture
// launch Debian's Chromium through puppeteer-core: headless, WebGL on
// SwiftShader (no GPU here), and none of Chromium's own traffic (updates,
// sync, QUIC probes), so that the page fetches from the server only.
// `more` adds puppeteer launch options (a protocol timeout, ...).
export function chromiumLaunchOptions(more = {}) {
  return {
    browser: 'chrome',
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: [
      '--no-sandbox',
      '--disable-gpu',
      '--use-angle=swiftshader',
      '--enable-unsafe-swiftshader',
      '--disable-background-networking',
      '--disable-component-update',
      '--disable-sync',
      '--no-first-run',
      '--disable-quic',
    ],
    ...more,
  };
}
