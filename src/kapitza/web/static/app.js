// The explorer page: the explorer (explorer.js) on this document, asking the JSON API under /api.
import { mount } from "./explorer.js";

// For tests and the console: the state, and where a point of the chart is on screen.
window.kapitza = mount(document);
