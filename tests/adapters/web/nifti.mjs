// The test pages' NIfTI reader (vtkjs.html, three.html): a NIfTI-1 file of float32 values, as
// browser.mjs writes halo-render's export: its dimensions and values.
export async function readNifti(url) {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`${url}: ${response.status}`);
  const buffer = await response.arrayBuffer();
  const view = new DataView(buffer);
  if (view.getInt32(0, true) !== 348) throw new Error(`${url}: not a little-endian NIfTI-1 file`);
  const dims = [1, 2, 3].map((i) => view.getInt16(40 + 2 * i, true));
  if (view.getInt16(70, true) !== 16) throw new Error(`${url}: datatype ${view.getInt16(70, true)}, not float32 (16)`);
  const offset = view.getFloat32(108, true);
  return { dims, values: new Float32Array(buffer.slice(offset, offset + 4 * dims[0] * dims[1] * dims[2])) };
}
