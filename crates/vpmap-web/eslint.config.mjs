// The page's modules (assets/js, browser ES modules) checked for names used but never imported
// or declared (`no-undef`): such a name is a ReferenceError only when its line runs, so no unit
// test that skips the line sees it. ESLint and its browser globals come with the browser tests'
// packages (e2e/package.json): `cd e2e && npm ci && npm run lint`; CI runs it before the
// browser tests.
import globals from './e2e/node_modules/globals/index.js';

export default [
  {
    files: ['assets/js/**/*.js'],
    languageOptions: { ecmaVersion: 2023, sourceType: 'module', globals: { ...globals.browser } },
    rules: { 'no-undef': 'error' },
  },
];
