// Typesets the mathematics that pymdownx.arithmatex (generic mode) leaves in the pages, with the
// KaTeX copy served by this site (docs/vendor/katex): no CDN, so the pages work offline.
(function () {
  function typeset(root) {
    renderMathInElement(root, {
      delimiters: [
        { left: "\\[", right: "\\]", display: true },
        { left: "\\(", right: "\\)", display: false },
      ],
      throwOnError: false,
    });
  }
  if (typeof document$ !== "undefined") {
    document$.subscribe(function (page) { typeset(page.body); });
  } else {
    document.addEventListener("DOMContentLoaded", function () { typeset(document.body); });
  }
})();
