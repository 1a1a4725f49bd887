// For the test pages (tests/adapters/web/*.html): window.render as browser.mjs calls it, draw
// with what the adapter printed through console.warn while it drew: { ...draw's result, warnings }.
export function renderWithWarnings(draw) {
  return async function render(options) {
    const warnings = [], warn = console.warn;
    console.warn = (...m) => { warnings.push(m.join(' ')); warn(...m); };
    try {
      return { ...(await draw(options)), warnings };
    } finally {
      console.warn = warn;
    }
  };
}
