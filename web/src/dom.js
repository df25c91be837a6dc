// A DOM element with properties, appended to `parent` when given.
export function el(tag, attrs = {}, parent = null) {
  const e = document.createElement(tag);
  Object.assign(e, attrs);
  if (parent) parent.appendChild(e);
  return e;
}
