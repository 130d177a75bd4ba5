// ESLint for the project's JavaScript: the viewer (browser modules), and the
// browser tests, benchmarks and helpers run by Node. scripts/lint_js.sh runs
// it with Prettier; the test command runs that script.
import js from '@eslint/js';
import globals from 'globals';

export default [
  {
    ignores: ['**/node_modules/**', '**/vendor/**'],
  },
  js.configs.recommended,
  {
    files: ['client/web/public/**/*.js'],
    languageOptions: {
      ecmaVersion: 2023,
      sourceType: 'module',
      globals: { ...globals.browser },
    },
  },
  {
    files: ['tests/**/*.mjs', 'bench/**/*.mjs', 'tests/lint/*.mjs'],
    languageOptions: {
      ecmaVersion: 2023,
      sourceType: 'module',
      globals: { ...globals.node, ...globals.browser },
    },
  },
  {
    rules: {
      // An unused argument documents a callback's signature.
      'no-unused-vars': ['error', { args: 'none', caughtErrors: 'none' }],
    },
  },
];
