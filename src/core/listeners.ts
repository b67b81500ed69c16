/**
 * Where a loop over `list` goes on after calling list[l] (`called`), which may have unsubscribed
 * itself or listeners before it (the list shifted under the loop): the listener after `called`, or,
 * when `called` is gone, the one that took its place. Without this the listener after one that
 * unsubscribed itself missed that event.
 */
export function nextListener(list: readonly unknown[], l: number, called: unknown): number {
  if (list[l] === called) return l + 1
  const at = list.indexOf(called)
  return at >= 0 ? at + 1 : l
}
