// A font file compressed to WOFF2 by Google's woff2 encoder (the npm
// package wawoff2): tests/integration/woff2_fonts.sh uploads it.
// Usage: node to_woff2.mjs IN.ttf OUT.woff2
import { readFileSync, writeFileSync } from 'node:fs';
import wawoff2 from 'wawoff2';

const [input, output] = process.argv.slice(2);
writeFileSync(output, await wawoff2.compress(readFileSync(input)));
