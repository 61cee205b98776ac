// The part of three.js the viewer uses, bundled by `npm run build` into three-bundle.js.
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
window.FOLDSIM_THREE = { THREE, GLTFLoader, OrbitControls };
