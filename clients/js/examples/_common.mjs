// Shared by the examples: the server URL (argv[2] or $SURFACED_URL), an output directory, and check().
import { Client } from '../surfaced.mjs';

export const url = process.argv[2] ?? process.env.SURFACED_URL ?? 'http://127.0.0.1:8080';
export const out = process.env.SURFACED_EXAMPLE_OUT ?? '.';
export const client = new Client(url);

export function check(condition, message) {
  console.log(`${condition ? 'ok  ' : 'FAIL'} ${message}`);
  if (!condition) process.exit(1);
}
